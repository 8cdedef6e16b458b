#pragma once
// Geometric multigrid for the linear solves of Newton's method in elasticity
// (vector Lagrange spaces, block size 2) on a nested MeshHierarchy.
//
// The Jacobian changes at every Newton step, so the coarse operators are
// Galerkin products PᵀJP (PCMG recomputes them whenever J changes); only the
// finest level is ever assembled. The vector prolongation is the scalar one of
// prolongation.hpp for each component, interleaved node by node:
//   P(2i + c, 2j + c) = P_c(i, j),
// where P_c uses component c's constrained nodes as its Dirichlet set. The
// Jacobian is the identity on constrained rows and columns, so PᵀJP is the
// identity on the coarse constrained block and the Galerkin product of the free
// block (see prolongation.hpp).
//
//   multigrid::ElasticityMultigrid mg(hierarchy, op.space(), op.data());
//   newton.pc_type = "mg";
//   newton.configure_preconditioner = [&mg](KSP ksp, Mat J) { mg.configure(ksp, J); };

#include <array>
#include <memory>
#include <vector>

#include "core/petsc/handles.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/elasticity/elasticity_data.hpp"
#include "fem/physics/elasticity/vector_space.hpp"
#include "multigrid/pcmg.hpp"

namespace warpfem::multigrid {

class ElasticityMultigrid {
 public:
  /// `finest` must live on hierarchy.finest(). Builds the DOF maps and
  /// distributions of the coarser levels and the vector prolongations.
  /// `level_owners`: cell owners of every level, as fem::nested_partitions()
  /// gives them (empty: computed here); the finest space should be built on
  /// the last entry. Throws warpfem::Error if the hierarchy does not match the space.
  ElasticityMultigrid(const fem::MeshHierarchy& hierarchy, const fem::VectorSpace<2>& finest,
                      const fem::ElasticityData& data, MultigridSettings settings = galerkin_defaults(),
                      const std::vector<std::vector<int>>& level_owners = {});
  ~ElasticityMultigrid();
  ElasticityMultigrid(const ElasticityMultigrid&) = delete;
  ElasticityMultigrid& operator=(const ElasticityMultigrid&) = delete;

  /// Makes `ksp`'s preconditioner this PCMG, with `jacobian` (the finest operator)
  /// as the KSP's operator. The options database may still override everything.
  void configure(KSP ksp, Mat jacobian) const;

  int num_levels() const { return static_cast<int>(prolongations_.size()) + 1; }
  /// Node distribution of a level below the finest (0 = coarsest).
  const fem::DofDistribution<2>& coarse_distribution(int level) const;
  /// The vector prolongation from level fine_level − 1 to fine_level.
  Mat prolongation(int fine_level) const {
    return prolongations_.at(static_cast<std::size_t>(fine_level - 1)).get();
  }

  static MultigridSettings galerkin_defaults() {
    MultigridSettings s;
    s.coarse_operators = MultigridSettings::CoarseOperators::galerkin;
    return s;
  }

 private:
  struct CoarseLevel;  // DOF map and distribution of a coarser level
  std::vector<std::unique_ptr<CoarseLevel>> coarse_;
  std::vector<petsc::Matrix> prolongations_;
  MultigridSettings settings_;
};

}  // namespace warpfem::multigrid
