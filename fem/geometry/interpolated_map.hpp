#pragma once
// The standard-FEM geometry of thesis §9.2.2 as a Map: the piecewise-linear
// (or bilinear) interpolant of f on a mesh of Ω0. Elements are straight-sided
// through the mapped vertices f(v), so the domain is the polygonal (polyhedral)
// approximation of Ω1 that ordinary FEM would mesh.
//   - built on the coarse mesh and kept under refinement: no shape recovery
//     (refined vertices stay on the straight coarse edges and faces);
//   - built on each level's own mesh: shape recovery (refined boundary
//     vertices are moved onto the exact boundary by f).
// In 3D the mesh must be tetrahedral (see MeshPointLocator).

#include <memory>

#include "fem/geometry/mesh_point_locator.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

template <int dim>
class InterpolatedMap final : public mapping::Map<dim> {
 public:
  /// Throws warpfem::Error for a 3D mesh of other cells than tetrahedra.
  InterpolatedMap(const Mesh<dim>& mesh, const mapping::Map<dim>& f);

  void eval(const Points<dim>& x0, Points<dim>& x) const override;
  void jacobian(const Points<dim>& x0, Jacobians<dim>& J) const override;
  void eval_with_jacobian(const Points<dim>& x0, Points<dim>& x, Jacobians<dim>& J) const override;
  std::string describe() const override;

 private:
  std::shared_ptr<const Mesh<dim>> mesh_;
  MeshPointLocator<dim> locator_;
  Points<dim> image_;  ///< f at every mesh vertex
};

}  // namespace warpfem::fem
