#include "multigrid/elasticity_multigrid.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "multigrid/prolongation.hpp"

namespace warpfem::multigrid {

struct ElasticityMultigrid::CoarseLevel {
  fem::DofMap dofs;
  fem::DofDistribution distribution;
  CoarseLevel(MPI_Comm comm, const warpfem::Mesh<2>& mesh, const fem::LagrangeElement<2>& element,
              const std::vector<int>& cell_owner)
      : dofs(mesh, element), distribution(comm, mesh, dofs, cell_owner) {}
};

namespace {

using ComponentMasks = std::array<std::vector<char>, 2>;

/// Constrained components of every node of the finest level (the operator's rule).
ComponentMasks finest_masks(const warpfem::Mesh<2>& mesh, const fem::DofMap& dofs,
                            const fem::ElasticityData& data) {
  const auto condition = fem::node_conditions(mesh, dofs, data);
  ComponentMasks m;
  for (int c = 0; c < 2; ++c) {
    m[static_cast<std::size_t>(c)].assign(condition.size(), 0);
    for (std::size_t d = 0; d < condition.size(); ++d)
      m[static_cast<std::size_t>(c)][d] = condition[d] && condition[d]->value[static_cast<std::size_t>(c)];
  }
  return m;
}

/// A coarse node is constrained where the fine node at the same place is: the
/// fine vertex at coarse node d is transfer.fine_vertex_of_node[d], and fine
/// vertex v is fine DOF v (DofMap numbers vertices first). The positions are
/// checked.
ComponentMasks coarser_masks(const ComponentMasks& fine, const fem::DofMap& fine_dofs,
                             const fem::DofMap& coarse_dofs, const warpfem::RefinedMesh& transfer) {
  const Index n = coarse_dofs.num_dofs();
  require(n <= static_cast<Index>(transfer.fine_vertex_of_node.size()),
          "ElasticityMultigrid: the coarse level has more DOFs than the refinement has nodes");
  const double scale = 1 + fine_dofs.dof_points().cwiseAbs().maxCoeff();
  ComponentMasks m;
  for (int c = 0; c < 2; ++c) m[static_cast<std::size_t>(c)].assign(static_cast<std::size_t>(n), 0);
  for (Index d = 0; d < n; ++d) {
    const Index f = transfer.fine_vertex_of_node[static_cast<std::size_t>(d)];
    if ((coarse_dofs.dof_points().row(d) - fine_dofs.dof_points().row(f)).cwiseAbs().maxCoeff() >
        1e-12 * scale)
      throw Error("ElasticityMultigrid: coarse DOF " + std::to_string(d) +
                  " is not at the fine vertex its refinement records; the hierarchy must come from "
                  "refine_uniformly");
    for (int c = 0; c < 2; ++c)
      m[static_cast<std::size_t>(c)][static_cast<std::size_t>(d)] =
          fine[static_cast<std::size_t>(c)][static_cast<std::size_t>(f)];
  }
  return m;
}

/// P(2i + c, 2j + c) = P_c(i, j) for the owned rows, block size 2.
petsc::Matrix interleave(const std::array<petsc::Matrix, 2>& scalar, const fem::DofDistribution& fine,
                         const fem::DofDistribution& coarse) {
  std::vector<PetscInt> ia{0}, ja;
  std::vector<PetscScalar> va;
  for (PetscInt r = 0; r < fine.num_owned(); ++r)
    for (int c = 0; c < 2; ++c) {
      const PetscInt row = fine.owned_begin() + r;
      PetscInt ncols = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      Mat P = scalar[static_cast<std::size_t>(c)].get();
      WARPFEM_PETSC_CHECK(MatGetRow(P, row, &ncols, &cols, &vals));
      for (PetscInt k = 0; k < ncols; ++k) {
        ja.push_back(2 * cols[k] + c);
        va.push_back(vals[k]);
      }
      WARPFEM_PETSC_CHECK(MatRestoreRow(P, row, &ncols, &cols, &vals));
      ia.push_back(static_cast<PetscInt>(ja.size()));
    }
  petsc::Matrix P;
  WARPFEM_PETSC_CHECK(MatCreate(fine.comm(), P.out()));
  WARPFEM_PETSC_CHECK(MatSetSizes(P.get(), 2 * fine.num_owned(), 2 * coarse.num_owned(),
                                  2 * fine.num_global(), 2 * coarse.num_global()));
  WARPFEM_PETSC_CHECK(MatSetType(P.get(), MATAIJ));
  WARPFEM_PETSC_CHECK(MatSetBlockSizes(P.get(), 2, 2));
  WARPFEM_PETSC_CHECK(MatSeqAIJSetPreallocationCSR(P.get(), ia.data(), ja.data(), va.data()));
  WARPFEM_PETSC_CHECK(MatMPIAIJSetPreallocationCSR(P.get(), ia.data(), ja.data(), va.data()));
  return P;
}

}  // namespace

ElasticityMultigrid::ElasticityMultigrid(const fem::MeshHierarchy& hierarchy, const fem::VectorSpace& finest,
                                         const fem::ElasticityData& data, MultigridSettings settings,
                                         const std::vector<std::vector<int>>& level_owners)
    : settings_(settings) {
  if (&hierarchy.finest() != &finest.mesh())
    throw Error("ElasticityMultigrid: the vector space does not live on the hierarchy's finest mesh",
                {.file = "", .key_path = "", .hint = "build the operator on hierarchy.finest()"});
  require(finest.components() == 2, "ElasticityMultigrid: needs a 2-component vector space");
  if (settings.prolongation == MultigridSettings::Prolongation::smoothed)
    throw Error("smoothed prolongations are implemented for the Poisson solver only",
                {.file = "",
                 .key_path = "solver.multigrid.prolongation",
                 .hint = "use \"geometric\" prolongations for elasticity"});
  const int levels = hierarchy.num_levels();
  const fem::LagrangeElement<2>& element = finest.dofs().element();
  // The coarse levels are partitioned like PoissonMultigridSolver's: nested, so
  // with a finest space built on the same partition (nested_partitions(...).back(),
  // as the elasticity app does) prolongation rows read other ranks' coarse
  // nodes only along the interface. Any other finest partition still works.
  require(level_owners.empty() || static_cast<int>(level_owners.size()) == levels,
          "ElasticityMultigrid: cell owners for " + std::to_string(level_owners.size()) +
              " levels, the hierarchy has " + std::to_string(levels));
  int size = 1;
  MPI_Comm_size(finest.comm(), &size);
  std::vector<std::vector<int>> computed;
  if (level_owners.empty()) computed = fem::nested_partitions(hierarchy, size);
  const std::vector<std::vector<int>>& owners = level_owners.empty() ? computed : level_owners;
  for (int l = 0; l + 1 < levels; ++l)
    coarse_.push_back(std::make_unique<CoarseLevel>(finest.comm(),
                                                    hierarchy.levels[static_cast<std::size_t>(l)], element,
                                                    owners[static_cast<std::size_t>(l)]));
  const auto dofs_at = [&](int l) -> const fem::DofMap& {
    return l + 1 == levels ? finest.dofs() : coarse_[static_cast<std::size_t>(l)]->dofs;
  };
  const auto distribution_at = [&](int l) -> const fem::DofDistribution& {
    return l + 1 == levels ? finest.nodes() : coarse_[static_cast<std::size_t>(l)]->distribution;
  };
  std::vector<ComponentMasks> masks(static_cast<std::size_t>(levels));
  masks.back() = finest_masks(hierarchy.finest(), finest.dofs(), data);
  for (int l = levels - 2; l >= 0; --l)
    masks[static_cast<std::size_t>(l)] =
        coarser_masks(masks[static_cast<std::size_t>(l) + 1], dofs_at(l + 1), dofs_at(l),
                      hierarchy.transfers[static_cast<std::size_t>(l)]);
  for (int l = 1; l < levels; ++l) {
    std::array<petsc::Matrix, 2> scalar;
    for (int c = 0; c < 2; ++c)
      scalar[static_cast<std::size_t>(c)] = assemble_prolongation(
          hierarchy, l,
          {.dofs = &dofs_at(l - 1),
           .distribution = &distribution_at(l - 1),
           .dirichlet = masks[static_cast<std::size_t>(l) - 1][static_cast<std::size_t>(c)]},
          {.dofs = &dofs_at(l),
           .distribution = &distribution_at(l),
           .dirichlet = masks[static_cast<std::size_t>(l)][static_cast<std::size_t>(c)]});
    prolongations_.push_back(interleave(scalar, distribution_at(l), distribution_at(l - 1)));
  }
}

ElasticityMultigrid::~ElasticityMultigrid() = default;

const fem::DofDistribution& ElasticityMultigrid::coarse_distribution(int level) const {
  require(level >= 0 && level + 1 < num_levels(), "ElasticityMultigrid::coarse_distribution: level " +
                                                      std::to_string(level) + " is not below the finest");
  return coarse_[static_cast<std::size_t>(level)]->distribution;
}

void ElasticityMultigrid::configure(KSP ksp, Mat jacobian) const {
  std::vector<Mat> interpolations;
  for (const auto& P : prolongations_) interpolations.push_back(P.get());
  configure_pcmg(ksp, interpolations, {jacobian}, settings_);
}

}  // namespace warpfem::multigrid
