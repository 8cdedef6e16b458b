#include "multigrid/geometric_multigrid.hpp"

#include <string>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "fem/dofs/cell_partition.hpp"
#include "multigrid/prolongation.hpp"

namespace warpfem::multigrid {

template <int dim>
struct GeometricMultigrid<dim>::CoarseLevel {
  fem::DofMap<dim> dofs;
  fem::DofDistribution<dim> distribution;
  CoarseLevel(MPI_Comm comm, const warpfem::Mesh<dim>& mesh, const fem::LagrangeElement<dim>& element,
              const std::vector<int>& cell_owner)
      : dofs(mesh, element), distribution(comm, mesh, dofs, cell_owner) {}
};

namespace {

/// Per component, per mesh DOF: 1 if constrained.
using ComponentMasks = std::vector<std::vector<char>>;

/// A coarse node is constrained where the fine node at the same place is: the
/// fine vertex at coarse node d is transfer.fine_vertex_of_node[d], and fine
/// vertex v is fine DOF v (DofMap numbers vertices first). The positions are
/// checked.
template <int dim>
ComponentMasks coarser_masks(const ComponentMasks& fine, const fem::DofMap<dim>& fine_dofs,
                             const fem::DofMap<dim>& coarse_dofs, const warpfem::RefinedMesh<dim>& transfer) {
  const Index n = coarse_dofs.num_dofs();
  require(n <= static_cast<Index>(transfer.fine_vertex_of_node.size()),
          "GeometricMultigrid: the coarse level has more DOFs than the refinement has nodes");
  const double scale = 1 + fine_dofs.dof_points().cwiseAbs().maxCoeff();
  ComponentMasks m(fine.size(), std::vector<char>(static_cast<std::size_t>(n), 0));
  for (Index d = 0; d < n; ++d) {
    const Index f = transfer.fine_vertex_of_node[static_cast<std::size_t>(d)];
    if ((coarse_dofs.dof_points().row(d) - fine_dofs.dof_points().row(f)).cwiseAbs().maxCoeff() >
        1e-12 * scale)
      throw Error("GeometricMultigrid: coarse DOF " + std::to_string(d) +
                  " is not at the fine vertex its refinement records; the hierarchy must come from "
                  "refine_uniformly");
    for (std::size_t c = 0; c < fine.size(); ++c)
      m[c][static_cast<std::size_t>(d)] = fine[c][static_cast<std::size_t>(f)];
  }
  return m;
}

/// P(k i + c, k j + c) = P_c(i, j) for the owned rows, block size k.
template <int dim>
petsc::Matrix interleave(const std::vector<petsc::Matrix>& scalar, const fem::DofDistribution<dim>& fine,
                         const fem::DofDistribution<dim>& coarse) {
  const PetscInt k = static_cast<PetscInt>(scalar.size());
  std::vector<PetscInt> ia{0}, ja;
  std::vector<PetscScalar> va;
  for (PetscInt r = 0; r < fine.num_owned(); ++r)
    for (PetscInt c = 0; c < k; ++c) {
      const PetscInt row = fine.owned_begin() + r;
      PetscInt ncols = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      Mat P = scalar[static_cast<std::size_t>(c)].get();
      WARPFEM_PETSC_CHECK(MatGetRow(P, row, &ncols, &cols, &vals));
      for (PetscInt j = 0; j < ncols; ++j) {
        ja.push_back(k * cols[j] + c);
        va.push_back(vals[j]);
      }
      WARPFEM_PETSC_CHECK(MatRestoreRow(P, row, &ncols, &cols, &vals));
      ia.push_back(static_cast<PetscInt>(ja.size()));
    }
  petsc::Matrix P;
  WARPFEM_PETSC_CHECK(MatCreate(fine.comm(), P.out()));
  WARPFEM_PETSC_CHECK(MatSetSizes(P.get(), k * fine.num_owned(), k * coarse.num_owned(),
                                  k * fine.num_global(), k * coarse.num_global()));
  WARPFEM_PETSC_CHECK(MatSetType(P.get(), MATAIJ));
  WARPFEM_PETSC_CHECK(MatSetBlockSizes(P.get(), k, k));
  WARPFEM_PETSC_CHECK(MatSeqAIJSetPreallocationCSR(P.get(), ia.data(), ja.data(), va.data()));
  WARPFEM_PETSC_CHECK(MatMPIAIJSetPreallocationCSR(P.get(), ia.data(), ja.data(), va.data()));
  return P;
}

/// The space of one level as the prolongation needs it.
template <int dim>
struct Level {
  const fem::DofMap<dim>* dofs = nullptr;
  const fem::DofDistribution<dim>* nodes = nullptr;
  ComponentMasks constrained;
};

/// Prolongations between consecutive levels (scalar: the scalar one itself).
template <int dim>
std::vector<petsc::Matrix> prolongations(const fem::MeshHierarchy<dim>& hierarchy,
                                         const std::vector<Level<dim>>& levels, int components) {
  std::vector<petsc::Matrix> out;
  for (std::size_t l = 1; l < levels.size(); ++l) {
    const Level<dim>& coarse = levels[l - 1];
    const Level<dim>& fine = levels[l];
    std::vector<petsc::Matrix> scalar;
    for (std::size_t c = 0; c < static_cast<std::size_t>(components); ++c)
      scalar.push_back(assemble_prolongation<dim>(
          hierarchy, static_cast<int>(l),
          {.dofs = coarse.dofs, .distribution = coarse.nodes, .dirichlet = coarse.constrained[c]},
          {.dofs = fine.dofs, .distribution = fine.nodes, .dirichlet = fine.constrained[c]}));
    out.push_back(components == 1 ? std::move(scalar.front())
                                  : interleave(scalar, *fine.nodes, *coarse.nodes));
  }
  return out;
}

/// PCMG's settings for these levels (see settings()).
template <int dim>
MultigridSettings resolved(MultigridSettings s, const fem::LagrangeElement<dim>& element, int components) {
  const int order = element.order();
  const bool smoothed = s.prolongation == MultigridSettings::Prolongation::smoothed;
  const bool galerkin = smoothed || s.coarse_operators == MultigridSettings::CoarseOperators::galerkin;
  if (smoothed && s.chebyshev_bounds == MultigridSettings::ChebyshevBounds::gershgorin)
    throw Error("Gershgorin bounds for the Chebyshev smoothers need rediscretized level operators",
                {.file = "",
                 .key_path = "solver.multigrid.chebyshev_bounds",
                 .hint = "use \"auto\" or \"estimate\" with smoothed prolongations"});
  // Smoothed: the Galerkin operators are formed by smooth() and handed to PCMG
  // level by level, which is configure_pcmg's "one operator per level" mode.
  if (smoothed) s.coarse_operators = MultigridSettings::CoarseOperators::rediscretization;
  // Automatic smoother: Chebyshev–Jacobi's V-cycle iterations grow level by level
  // for quadratic tetrahedra on non-uniform meshes (the two-grid factor itself
  // grows, with any interval or number of steps), Chebyshev–SOR's stay flat;
  // elsewhere Chebyshev–Jacobi is as flat and cheaper. Gershgorin bounds ask for
  // Jacobi; vector problems (elasticity, measured with Jacobi) keep it too.
  using Smoother = MultigridSettings::Smoother;
  if (s.smoother == Smoother::automatic)
    s.smoother = element.cell_type() == CellType::tetrahedron && order >= 2 && components == 1 &&
                         s.chebyshev_bounds != MultigridSettings::ChebyshevBounds::gershgorin
                     ? Smoother::chebyshev_sor
                     : Smoother::chebyshev_jacobi;
  // Automatic Chebyshev bounds: Gershgorin's is tight for first-order stiffness
  // matrices (no eigenvalue estimates at set-up), loose for higher orders;
  // symmetric SOR's λmax ≤ 1 is what the estimate finds (0.999) for scalar
  // problems, whose matrices are symmetric positive definite.
  using Bounds = MultigridSettings::ChebyshevBounds;
  if (s.chebyshev_bounds == Bounds::automatic) {
    if (order == 1 && !galerkin && s.smoother == Smoother::chebyshev_jacobi)
      s.chebyshev_bounds = Bounds::gershgorin;
    else if (s.smoother == Smoother::chebyshev_sor && components == 1)
      s.chebyshev_bounds = Bounds::ssor;
    else
      s.chebyshev_bounds = Bounds::estimate;
  }
  return s;
}

/// Cell owners of every level for the Galerkin constructor: nested in 2D; in
/// 3D (no nested partition yet) each level cut along its own Morton curve.
template <int dim>
std::vector<std::vector<int>> level_partitions(const fem::MeshHierarchy<dim>& hierarchy, int parts) {
  if constexpr (dim == 2) {
    return fem::nested_partitions(hierarchy, parts);
  } else {
    std::vector<std::vector<int>> owners;
    for (const auto& mesh : hierarchy.levels) owners.push_back(fem::partition_cells(mesh, parts));
    return owners;
  }
}

}  // namespace

template <int dim>
GeometricMultigrid<dim>::GeometricMultigrid(const fem::MeshHierarchy<dim>& hierarchy,
                                            const std::vector<const fem::Problem<dim>*>& levels,
                                            const MultigridSettings& settings) {
  require(!levels.empty() && static_cast<int>(levels.size()) == hierarchy.num_levels(),
          "GeometricMultigrid: " + std::to_string(levels.size()) + " level problems for a hierarchy of " +
              std::to_string(hierarchy.num_levels()) + " levels");
  components_ = levels.back()->components();
  settings_ = resolved(settings, levels.back()->dofs().element(), components_);
  std::vector<Level<dim>> spaces;
  for (const fem::Problem<dim>* p : levels) {
    require(p->components() == components_, "GeometricMultigrid: the levels differ in components");
    spaces.push_back({.dofs = &p->dofs(), .nodes = &p->nodes(), .constrained = p->constrained()});
  }
  prolongations_ = prolongations(hierarchy, spaces, components_);
}

template <int dim>
GeometricMultigrid<dim>::GeometricMultigrid(const fem::MeshHierarchy<dim>& hierarchy,
                                            const fem::Problem<dim>& finest,
                                            const MultigridSettings& settings,
                                            const std::vector<std::vector<int>>& level_owners)
    : components_(finest.components()) {
  if (&hierarchy.finest() != &finest.mesh())
    throw Error("GeometricMultigrid: the problem does not live on the hierarchy's finest mesh",
                {.file = "", .key_path = "", .hint = "build the problem on hierarchy.finest()"});
  if (settings.prolongation == MultigridSettings::Prolongation::smoothed)
    throw Error(
        "smoothed prolongations need the operator at set-up: they are available with "
        "rediscretized levels (the Poisson solver) only",
        {.file = "",
         .key_path = "solver.multigrid.prolongation",
         .hint = "use \"geometric\" prolongations for elasticity"});
  settings_ = resolved(settings, finest.dofs().element(), components_);
  const int levels = hierarchy.num_levels();
  // The coarse levels are partitioned like the rediscretized ones: nested, so
  // with a finest problem built on the same partition (nested_partitions(...).back())
  // prolongation rows read other ranks' coarse nodes only along the interface.
  // Any other finest partition still works.
  require(level_owners.empty() || static_cast<int>(level_owners.size()) == levels,
          "GeometricMultigrid: cell owners for " + std::to_string(level_owners.size()) +
              " levels, the hierarchy has " + std::to_string(levels));
  int size = 1;
  MPI_Comm_size(finest.comm(), &size);
  std::vector<std::vector<int>> computed;
  if (level_owners.empty()) computed = level_partitions(hierarchy, size);
  const std::vector<std::vector<int>>& owners = level_owners.empty() ? computed : level_owners;
  for (int l = 0; l + 1 < levels; ++l)
    coarse_.push_back(
        std::make_unique<CoarseLevel>(finest.comm(), hierarchy.levels[static_cast<std::size_t>(l)],
                                      finest.dofs().element(), owners[static_cast<std::size_t>(l)]));
  std::vector<Level<dim>> spaces(static_cast<std::size_t>(levels));
  spaces.back() = {.dofs = &finest.dofs(), .nodes = &finest.nodes(), .constrained = finest.constrained()};
  for (int l = levels - 2; l >= 0; --l) {
    const std::size_t i = static_cast<std::size_t>(l);
    spaces[i] = {.dofs = &coarse_[i]->dofs,
                 .nodes = &coarse_[i]->distribution,
                 .constrained = coarser_masks(spaces[i + 1].constrained, *spaces[i + 1].dofs,
                                              coarse_[i]->dofs, hierarchy.transfers[i])};
  }
  prolongations_ = prolongations(hierarchy, spaces, components_);
}

template <int dim>
GeometricMultigrid<dim>::~GeometricMultigrid() = default;

template <int dim>
const fem::DofDistribution<dim>& GeometricMultigrid<dim>::coarse_distribution(int level) const {
  require(level >= 0 && level < static_cast<int>(coarse_.size()),
          "GeometricMultigrid::coarse_distribution: level " + std::to_string(level) +
              " is not a coarse level built here");
  return coarse_[static_cast<std::size_t>(level)]->distribution;
}

template <int dim>
void GeometricMultigrid<dim>::smooth(Mat finest) {
  require(settings_.prolongation == MultigridSettings::Prolongation::smoothed,
          "GeometricMultigrid::smooth: the settings ask for geometric prolongations");
  std::vector<Mat> geometric;
  for (const auto& P : prolongations_) geometric.push_back(P.get());
  smoothed_ = smooth_prolongations(finest, geometric);
}

template <int dim>
void GeometricMultigrid<dim>::configure(KSP ksp, const std::vector<Mat>& operators) const {
  std::vector<Mat> interpolations, ops;
  for (int l = 1; l < num_levels(); ++l) interpolations.push_back(interpolation(l));
  if (settings_.prolongation == MultigridSettings::Prolongation::smoothed) {
    require(!smoothed_.operators.empty() || num_levels() == 1,
            "GeometricMultigrid::configure: call smooth() before configure() with smoothed prolongations");
    // Every level's operator is given: PCMG computes no Galerkin product itself.
    for (const auto& A : smoothed_.operators) ops.push_back(A.get());
    ops.push_back(operators.back());
  } else {
    ops = operators;
  }
  configure_pcmg(ksp, interpolations, ops, settings_);
}

template class GeometricMultigrid<2>;
template class GeometricMultigrid<3>;

}  // namespace warpfem::multigrid
