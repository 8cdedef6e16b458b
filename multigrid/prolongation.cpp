#include "multigrid/prolongation.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>

#include "core/error.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::multigrid {
namespace {

constexpr double kZero = 1e-13;  // |φ| below this is a structural zero

/// Reference coordinates of the vertices of a cell (LagrangeElement conventions).
Point<2> reference_vertex(fem::CellType type, int k) {
  static const double tri[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  static const double quad[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const double* p = type == fem::CellType::triangle ? tri[k] : quad[k];
  return {p[0], p[1]};
}

/// Coarse shape values at the fine nodes, per child configuration. A child is
/// identified by the positions of its vertices in the parent's reference cell;
/// those are multiples of 1/2, so they encode in base 9 per vertex.
class ChildTables {
 public:
  ChildTables(const fem::LagrangeElement& element)
      : element_(element), geometry_(element.cell_type(), 1), slot_(6561, -1) {}

  /// Table (fine nodes x coarse DOFs) for a child whose vertices sit at `eta`.
  const MatrixX& get(const Points<2>& eta) {
    int key = 0;
    for (Index a = eta.rows() - 1; a >= 0; --a) {
      const int ix = static_cast<int>(std::lround(2 * eta(a, 0))),
                iy = static_cast<int>(std::lround(2 * eta(a, 1)));
      key = 9 * key + 3 * ix + iy;
    }
    int& s = slot_[static_cast<std::size_t>(key)];
    if (s < 0) {
      // Fine nodes in the child's reference cell, mapped into the parent's by the child's P1/Q1 geometry.
      const MatrixX geo = geometry_.values(element_.nodes());
      const Points<2> in_parent = geo * eta;
      tables_.push_back(element_.values(in_parent));
      s = static_cast<int>(tables_.size()) - 1;
    }
    return tables_[static_cast<std::size_t>(s)];
  }

 private:
  const fem::LagrangeElement& element_;
  fem::LagrangeElement geometry_;
  std::vector<int> slot_;
  std::deque<MatrixX> tables_;  // a deque: references stay valid as tables are added
};

void check_spaces(const fem::MeshHierarchy& h, int fine_level, const LevelSpace& coarse,
                  const LevelSpace& fine) {
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
  require(coarse.dirichlet.empty() ||
              coarse.dirichlet.size() == static_cast<std::size_t>(coarse.dofs->num_dofs()),
          "assemble_prolongation: coarse Dirichlet mask has the wrong size");
  require(fine.dirichlet.empty() || fine.dirichlet.size() == static_cast<std::size_t>(fine.dofs->num_dofs()),
          "assemble_prolongation: fine Dirichlet mask has the wrong size");
}

}  // namespace

petsc::Matrix assemble_prolongation(const fem::MeshHierarchy& hierarchy, int fine_level,
                                    const LevelSpace& coarse, const LevelSpace& fine) {
  check_spaces(hierarchy, fine_level, coarse, fine);
  const std::size_t fl = static_cast<std::size_t>(fine_level);
  const fem::Mesh<2>& cmesh = hierarchy.levels[fl - 1];
  const fem::Mesh<2>& fmesh = hierarchy.levels[fl];
  const auto& parent = hierarchy.transfers[fl - 1].cell_parent;
  const auto& vparents = hierarchy.transfers[fl - 1].vertex_parents;
  const fem::DofDistribution& fdist = *fine.distribution;
  const fem::DofDistribution& cdist = *coarse.distribution;
  const fem::IndexTable& fdofs = fine.dofs->cell_dofs();
  const fem::IndexTable& cdofs = coarse.dofs->cell_dofs();
  const int n = static_cast<int>(fdofs.cols());  // fine nodes = coarse DOFs per cell
  const int nv = fem::vertices_per_cell(fmesh.cell_type);
  const auto is_dirichlet = [](const LevelSpace& s, Index d) {
    return !s.dirichlet.empty() && s.dirichlet[static_cast<std::size_t>(d)];
  };

  // Each owned fine row is filled from the first local fine cell containing it
  // (the owner of a DOF always assembles a cell containing it).
  const PetscInt rows = fdist.num_owned();
  std::vector<PetscInt> count(static_cast<std::size_t>(rows), -1), cols(static_cast<std::size_t>(rows) * n);
  std::vector<PetscScalar> vals(static_cast<std::size_t>(rows) * n);
  ChildTables tables(fine.dofs->element());
  // refine_uniformly makes fine cells 4c .. 4c+3 the children of coarse cell c,
  // always in the same pattern, so the child's table depends only on f − 4c:
  // it is found once per child index from the vertex parents (random accesses
  // into vertex_parents dominated this loop) and reused.
  bool fixed_layout = true;
  for (std::size_t f = 0; f < parent.size() && fixed_layout; ++f)
    fixed_layout = parent[f] == static_cast<Index>(f / 4);
  const MatrixX* by_child[4] = {nullptr, nullptr, nullptr, nullptr};
  Points<2> eta(nv, 2);
  for (Index f : fdist.local_cells()) {
    const Index c = parent[static_cast<std::size_t>(f)];
    bool todo = false;
    for (int k = 0; k < n && !todo; ++k) {
      const Index d = fdofs(f, k);
      todo = fdist.owns(d) && count[static_cast<std::size_t>(fdist.global(d) - fdist.owned_begin())] < 0;
    }
    if (!todo) continue;
    const MatrixX** cached = fixed_layout ? &by_child[f - 4 * c] : nullptr;
    if (!cached || !*cached) {
      for (int a = 0; a < nv; ++a) {
        const auto& ps = vparents[static_cast<std::size_t>(fmesh.cells(f, a))];
        Point<2> sum = Point<2>::Zero();
        for (Index p : ps) {
          int local = 0;
          while (local < nv && cmesh.cells(c, local) != p) ++local;
          if (local == nv) throw Error("assemble_prolongation: a fine vertex is not inside its parent cell");
          sum += reference_vertex(cmesh.cell_type, local);
        }
        eta.row(a) = (sum / static_cast<double>(ps.size())).transpose();
      }
      const MatrixX& t = tables.get(eta);
      if (cached) *cached = &t;
    }
    const MatrixX& table = cached ? **cached : tables.get(eta);
    for (int k = 0; k < n; ++k) {
      const Index d = fdofs(f, k);
      if (!fdist.owns(d)) continue;
      const std::size_t row = static_cast<std::size_t>(fdist.global(d) - fdist.owned_begin());
      if (count[row] >= 0) continue;
      PetscInt m = 0;
      const bool fixed = is_dirichlet(fine, d);
      for (int j = 0; j < n; ++j) {
        const double v = table(k, j);
        if (std::abs(v) < kZero) continue;
        const Index cd = cdofs(c, j);
        if (fixed != is_dirichlet(coarse, cd)) continue;   // no coupling across the eliminated block
        if (fixed && std::abs(v - 1.0) > 1e-10) continue;  // Dirichlet block: injection only
        cols[row * n + m] = cdist.global(cd);
        vals[row * n + m] = fixed ? 1.0 : v;
        ++m;
      }
      count[row] = m;
    }
  }
  // CSR with sorted columns.
  std::vector<PetscInt> ia(static_cast<std::size_t>(rows) + 1, 0), ja;
  std::vector<PetscScalar> va;
  ja.reserve(static_cast<std::size_t>(rows) * 4);
  va.reserve(static_cast<std::size_t>(rows) * 4);
  std::vector<int> order(static_cast<std::size_t>(n));
  for (std::size_t r = 0; r < static_cast<std::size_t>(rows); ++r) {
    if (count[r] < 0) throw Error("assemble_prolongation: an owned fine DOF lies in no local cell");
    const PetscInt* cr = &cols[r * n];
    std::iota(order.begin(), order.begin() + count[r], 0);
    std::sort(order.begin(), order.begin() + count[r], [cr](int a, int b) { return cr[a] < cr[b]; });
    for (PetscInt k = 0; k < count[r]; ++k) {
      ja.push_back(cr[order[k]]);
      va.push_back(vals[r * n + order[k]]);
    }
    ia[r + 1] = static_cast<PetscInt>(ja.size());
  }
  petsc::Matrix P;
  WARPFEM_PETSC_CHECK(MatCreate(fdist.comm(), P.out()));
  WARPFEM_PETSC_CHECK(MatSetSizes(P.get(), rows, cdist.num_owned(), fdist.num_global(), cdist.num_global()));
  WARPFEM_PETSC_CHECK(MatSetType(P.get(), MATAIJ));
  WARPFEM_PETSC_CHECK(MatSeqAIJSetPreallocationCSR(P.get(), ia.data(), ja.data(), va.data()));
  WARPFEM_PETSC_CHECK(MatMPIAIJSetPreallocationCSR(P.get(), ia.data(), ja.data(), va.data()));
  return P;
}

}  // namespace warpfem::multigrid
