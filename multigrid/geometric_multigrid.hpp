#pragma once
// Geometric multigrid on a nested MeshHierarchy for any fem::Problem, scalar
// or vector (block size = components): the prolongations between the levels'
// spaces, optionally smoothed, and one PCMG configuration (pcmg.hpp).
//
// Two ways to get the level operators:
//  - rediscretization: a problem on every level (Poisson's linear solve);
//  - Galerkin PᵀAP: only the finest problem; the coarser spaces are built here
//    and PCMG recomputes the products whenever the operator changes (Newton's
//    Jacobians in elasticity).
//
// The vector prolongation is the scalar one of prolongation.hpp for each
// component, interleaved node by node, P(k i + c, k j + c) = P_c(i, j), where
// P_c uses component c's constrained DOFs as its Dirichlet set. Operators are
// the identity on constrained rows and columns, so PᵀAP is the identity on the
// coarse constrained block and the Galerkin product of the free block.
//
//   GeometricMultigrid mg(hierarchy, op, settings);          // Galerkin, finest only
//   newton.configure_preconditioner = [&mg](KSP ksp, Mat J) { mg.configure(ksp, {J}); };

#include <memory>
#include <vector>

#include "core/petsc/handles.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/problem.hpp"
#include "multigrid/pcmg.hpp"
#include "multigrid/smoothed_prolongation.hpp"

namespace warpfem::multigrid {

template <int dim>
class GeometricMultigrid {
 public:
  /// Rediscretized levels: `levels[l]` is the problem on hierarchy level l
  /// (coarse to fine), all with the same element and components. With smoothed
  /// prolongations call smooth() with the finest operator before configure().
  GeometricMultigrid(const fem::MeshHierarchy<dim>& hierarchy,
                     const std::vector<const fem::Problem<dim>*>& levels, const MultigridSettings& settings);
  /// Galerkin levels below `finest`, which must live on hierarchy.finest(): the
  /// coarser DOF maps and distributions are built here, a coarse unknown is
  /// constrained where the finer level's at the same node is. `level_owners`:
  /// cell owners of every level as fem::nested_partitions() gives them (empty:
  /// computed here: nested in 2D, each level cut along its own Morton curve in
  /// 3D); the finest problem should be built on the last entry.
  /// Throws warpfem::Error if the hierarchy does not match the problem or the
  /// settings ask for smoothed prolongations (they need the operator at set-up).
  GeometricMultigrid(const fem::MeshHierarchy<dim>& hierarchy, const fem::Problem<dim>& finest,
                     const MultigridSettings& settings = galerkin_defaults(),
                     const std::vector<std::vector<int>>& level_owners = {});
  ~GeometricMultigrid();
  GeometricMultigrid(const GeometricMultigrid&) = delete;
  GeometricMultigrid& operator=(const GeometricMultigrid&) = delete;

  int num_levels() const { return static_cast<int>(prolongations_.size()) + 1; }
  int components() const { return components_; }
  /// The settings PCMG gets: automatic Chebyshev bounds resolved (Gershgorin's
  /// for first-order rediscretized levels with chebyshev_jacobi, else
  /// estimates), smoothed levels handed over as given operators.
  const MultigridSettings& settings() const { return settings_; }
  /// Node distribution of a level below the finest built here (Galerkin constructor only).
  const fem::DofDistribution<dim>& coarse_distribution(int level) const;
  /// The geometric prolongation from level fine_level − 1 to fine_level.
  Mat prolongation(int fine_level) const {
    return prolongations_.at(static_cast<std::size_t>(fine_level - 1)).get();
  }
  /// What PCMG interpolates with: prolongation(), or its smoothed version.
  Mat interpolation(int fine_level) const {
    const std::size_t i = static_cast<std::size_t>(fine_level - 1);
    return smoothed_.interpolations.empty() ? prolongations_.at(i).get()
                                            : smoothed_.interpolations.at(i).get();
  }

  /// Smoothed prolongations: P̃ and the Galerkin operators of the coarser levels
  /// from the finest operator (smoothed_prolongation.hpp). Only with
  /// settings().prolongation == smoothed.
  void smooth(Mat finest);

  /// Makes `ksp`'s preconditioner this PCMG with the finest of `operators` as
  /// the KSP's operator. `operators`: one per level (coarse to fine) for
  /// rediscretized levels, else the finest only. Call KSPSetFromOptions (and
  /// then reconcile_chebyshev_bounds with settings()) for the options database
  /// to override the defaults; Newton's SNESSetFromOptions does the former.
  void configure(KSP ksp, const std::vector<Mat>& operators) const;

  static MultigridSettings galerkin_defaults() {
    MultigridSettings s;
    s.coarse_operators = MultigridSettings::CoarseOperators::galerkin;
    return s;
  }

 private:
  struct CoarseLevel;  // DOF map and distribution of a coarser level (Galerkin constructor)
  std::vector<std::unique_ptr<CoarseLevel>> coarse_;
  std::vector<petsc::Matrix> prolongations_;
  SmoothedLevels smoothed_;
  MultigridSettings settings_;
  int components_ = 1;
};

extern template class GeometricMultigrid<2>;
extern template class GeometricMultigrid<3>;

}  // namespace warpfem::multigrid
