#include "multigrid/prolongation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/csr_matrix.hpp"
#include "core/prefault.hpp"

namespace warpfem::multigrid {

template <int dim>
std::vector<MatrixX> child_prolongation_tables(const fem::LagrangeElement<dim>& element) {
  const fem::LagrangeElement<dim> geometry(element.cell_type(), 1);
  const MatrixX to_child = geometry.values(element.nodes());
  const int children = warpfem::refinement_table(element.cell_type()).children;
  std::vector<MatrixX> tables(static_cast<std::size_t>(children));
  for (int k = 0; k < children; ++k)
    tables[static_cast<std::size_t>(k)] =
        element.values(to_child * warpfem::child_reference_vertices<dim>(element.cell_type(), k));
  return tables;
}

template std::vector<MatrixX> child_prolongation_tables(const fem::LagrangeElement<2>&);
template std::vector<MatrixX> child_prolongation_tables(const fem::LagrangeElement<3>&);

namespace {

constexpr double kZero = 1e-13;  // |φ| below this is a structural zero

template <int dim, class Space>
void check_spaces(const fem::MeshHierarchy<dim>& h, int fine_level, const Space& coarse, const Space& fine) {
  require(fine_level >= 1 && fine_level < h.num_levels(), "assemble_prolongation: fine level " +
                                                              std::to_string(fine_level) + " is not in 1.." +
                                                              std::to_string(h.num_levels() - 1));
  require(coarse.dofs && coarse.distribution && fine.dofs && fine.distribution,
          "assemble_prolongation: LevelSpace without DOF map or distribution");
  const auto& ce = coarse.dofs->element();
  const auto& fe = fine.dofs->element();
  if (ce.cell_type() != fe.cell_type() || ce.order() != fe.order())
    throw Error("prolongation between different elements " + ce.name() + " and " + fe.name(),
                {.file = "", .key_path = "", .hint = "build every level with the same element order"});
  require(coarse.dofs->cell_dofs().rows() == h.levels[static_cast<std::size_t>(fine_level - 1)].num_cells() &&
              fine.dofs->cell_dofs().rows() == h.levels[static_cast<std::size_t>(fine_level)].num_cells(),
          "assemble_prolongation: the DOF maps do not belong to the hierarchy's levels");
  require(h.levels[static_cast<std::size_t>(fine_level)].num_cells() ==
              warpfem::RefinedMesh<dim>::children_per_cell *
                  h.levels[static_cast<std::size_t>(fine_level - 1)].num_cells(),
          "assemble_prolongation: level " + std::to_string(fine_level) +
              " is not a uniform refinement of the level below (levels must come from refine_uniformly)");
  require(coarse.dirichlet.empty() ||
              coarse.dirichlet.size() == static_cast<std::size_t>(coarse.dofs->num_dofs()),
          "assemble_prolongation: coarse Dirichlet mask has the wrong size");
  require(fine.dirichlet.empty() || fine.dirichlet.size() == static_cast<std::size_t>(fine.dofs->num_dofs()),
          "assemble_prolongation: fine Dirichlet mask has the wrong size");
}

/// assemble_prolongation for any dimension (`Space`: a LevelSpace of that dimension).
template <int dim, class Space>
petsc::Matrix assemble(const fem::MeshHierarchy<dim>& hierarchy, int fine_level, const Space& coarse,
                       const Space& fine) {
  check_spaces(hierarchy, fine_level, coarse, fine);
  const fem::DofDistribution<dim>& fdist = *fine.distribution;
  const fem::DofDistribution<dim>& cdist = *coarse.distribution;
  const warpfem::IndexTable& fdofs = fine.dofs->cell_dofs();
  const warpfem::IndexTable& cdofs = coarse.dofs->cell_dofs();
  const int n = static_cast<int>(fdofs.cols());  // fine nodes = coarse DOFs per cell
  const auto is_dirichlet = [](const Space& s, Index d) {
    return !s.dirichlet.empty() && s.dirichlet[static_cast<std::size_t>(d)];
  };

  // Each owned fine row is filled from the first local fine cell containing it
  // (the owner of a DOF always assembles a cell containing it). Pass 1 finds
  // that cell and the DOF's place in it and counts the row's entries; pass 2
  // writes the rows straight into the compressed arrays, in row order.
  const PetscInt rows = fdist.num_owned();
  constexpr std::int64_t kUnset = -1;
  std::vector<std::int64_t> source(static_cast<std::size_t>(rows), kUnset);  // fine cell * n + place
  // refine_uniformly makes fine cells 2^dim c … the children of coarse cell c,
  // always in the same layout, so a child's table depends only on f − 2^dim c.
  const std::vector<MatrixX> tables = child_prolongation_tables(fine.dofs->element());
  // The entries of fine DOF d at place k of fine cell f: coarse DOF j of the
  // parent with a nonzero coarse shape value (no coupling across the
  // eliminated Dirichlet block; Dirichlet rows are injections).
  const auto for_each_entry = [&](Index f, int k, auto&& emit) {
    const Index c = warpfem::RefinedMesh<dim>::parent_of(f);
    const MatrixX& table =
        tables[static_cast<std::size_t>(f - warpfem::RefinedMesh<dim>::children_per_cell * c)];
    const bool fixed = is_dirichlet(fine, fdofs(f, k));
    for (int j = 0; j < n; ++j) {
      const double v = table(k, j);
      if (std::abs(v) < kZero) continue;
      const Index cd = cdofs(c, j);
      if (fixed != is_dirichlet(coarse, cd)) continue;   // no coupling across the eliminated block
      if (fixed && std::abs(v - 1.0) > 1e-10) continue;  // Dirichlet block: injection only
      emit(cdist.global(cd), fixed ? 1.0 : v);
    }
  };
  // Under MPI the rows are written split the way MATMPIAIJ stores them: coarse
  // columns of this rank local (diagonal block), the others global.
  int size = 1;
  MPI_Comm_size(fdist.comm(), &size);
  const bool split = size > 1;
  const PetscInt cbegin = cdist.owned_begin(), cend = cdist.owned_end();
  const auto is_own = [&](PetscInt col) { return !split || (col >= cbegin && col < cend); };
  petsc::OwnedRows csr, off;
  csr.row_ptr.assign(static_cast<std::size_t>(rows) + 1, 0);
  if (split) off.row_ptr.assign(static_cast<std::size_t>(rows) + 1, 0);
  for (Index f : fdist.local_cells())
    for (int k = 0; k < n; ++k) {
      const Index d = fdofs(f, k);
      if (!fdist.owns(d)) continue;
      const std::size_t row = static_cast<std::size_t>(fdist.global(d) - fdist.owned_begin());
      if (source[row] != kUnset) continue;
      source[row] = static_cast<std::int64_t>(f) * n + k;
      PetscInt m = 0, m_off = 0;
      for_each_entry(f, k, [&](PetscInt col, double) { ++(is_own(col) ? m : m_off); });
      csr.row_ptr[row + 1] = m;
      if (split) off.row_ptr[row + 1] = m_off;
    }
  for (std::size_t r = 0; r < static_cast<std::size_t>(rows); ++r) {
    if (source[r] == kUnset) throw Error("assemble_prolongation: an owned fine DOF lies in no local cell");
    csr.row_ptr[r + 1] += csr.row_ptr[r];
    if (split) off.row_ptr[r + 1] += off.row_ptr[r];
  }
  // A row has at most n entries: each is sorted in place by insertion.
  resize_prefaulted(csr.cols, static_cast<std::size_t>(csr.row_ptr[static_cast<std::size_t>(rows)]));
  resize_prefaulted(csr.vals, csr.cols.size());
  if (split) {
    off.cols.resize(static_cast<std::size_t>(off.row_ptr[static_cast<std::size_t>(rows)]));
    off.vals.resize(off.cols.size());
  }
  const auto insert = [](PetscInt* oc, PetscScalar* ov, PetscInt& m, PetscInt col, double val) {
    PetscInt j = m++;
    for (; j > 0 && oc[j - 1] > col; --j) oc[j] = oc[j - 1], ov[j] = ov[j - 1];
    oc[j] = col, ov[j] = val;
  };
  for (std::size_t r = 0; r < static_cast<std::size_t>(rows); ++r) {
    PetscInt* oc = csr.cols.data() + csr.row_ptr[r];
    PetscScalar* ov = csr.vals.data() + csr.row_ptr[r];
    PetscInt m = 0, m_off = 0;
    for_each_entry(
        static_cast<Index>(source[r] / n), static_cast<int>(source[r] % n), [&](PetscInt col, double val) {
          if (is_own(col))
            insert(oc, ov, m, split ? col - cbegin : col, val);
          else
            insert(off.cols.data() + off.row_ptr[r], off.vals.data() + off.row_ptr[r], m_off, col, val);
        });
  }
  if (split)
    return petsc::adopt_split_rows(fdist.comm(), std::move(csr), std::move(off), cdist.num_owned(),
                                   fdist.num_global(), cdist.num_global(), {.inodes = false});
  return petsc::adopt_owned_rows(fdist.comm(), std::move(csr), cdist.num_owned(), cdist.owned_begin(),
                                 fdist.num_global(), cdist.num_global(), {.inodes = false});
}

}  // namespace

template <int dim>
petsc::Matrix assemble_prolongation(const fem::MeshHierarchy<dim>& hierarchy, int fine_level,
                                    const LevelSpace<dim>& coarse, const LevelSpace<dim>& fine) {
  return assemble(hierarchy, fine_level, coarse, fine);
}

template petsc::Matrix assemble_prolongation(const fem::MeshHierarchy<2>&, int, const LevelSpace<2>&,
                                             const LevelSpace<2>&);
template petsc::Matrix assemble_prolongation(const fem::MeshHierarchy<3>&, int, const LevelSpace<3>&,
                                             const LevelSpace<3>&);

}  // namespace warpfem::multigrid
