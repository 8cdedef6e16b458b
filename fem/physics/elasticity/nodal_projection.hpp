#pragma once
// Lumped L2 projection of quadrature-point data (stresses, det F) onto a
// continuous P1/Q1 field of the same mesh and partition, for visualization:
//   v_k = Σ_cells ∫ v φ_k dx / Σ_cells ∫ φ_k dx   (φ_k ≥ 0, so never divides by zero).
// Uses only the cached WarpedGeometry.

#include <vector>

#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/geometry/warped_geometry.hpp"

namespace warpfem::fem {

template <int dim>
class NodalProjection {
 public:
  /// `geometry` must cover exactly this rank's cells of the partition of `mesh`:
  /// `cell_owner` (the one the geometry's space was built with), or
  /// partition_cells() if that is empty.
  NodalProjection(MPI_Comm comm, const Mesh<dim>& mesh, const WarpedGeometry<dim>& geometry,
                  const std::vector<int>& cell_owner = {});
  NodalProjection(const NodalProjection&) = delete;
  NodalProjection& operator=(const NodalProjection&) = delete;

  /// `values[i][q]`: value at quadrature point q of geometry cell i. Returns the projected
  /// values at distribution().relevant_dofs(). Collective.
  VectorX project(const std::vector<std::vector<double>>& values) const;

  const DofMap<dim>& dofs() const { return dofs_; }
  const DofDistribution<dim>& distribution() const { return dist_; }

 private:
  /// sum_k = Σ_cells ∫ value(i, q) φ_k dx (value at quadrature point q of geometry cell i).
  template <class Value>
  void accumulate(Vec sum, Value&& value) const;

  const WarpedGeometry<dim>& geometry_;
  DofMap<dim> dofs_;
  DofDistribution<dim> dist_;
  petsc::Vector weights_;
};

}  // namespace warpfem::fem
