#pragma once
// The standard-FEM geometry of thesis §9.2.2 as a Map: the piecewise-linear
// (or bilinear) interpolant of f on a mesh of Ω0. Elements are straight-sided
// through the mapped vertices f(v), so the domain is the polygonal
// approximation of Ω1 that ordinary FEM would mesh.
//   - built on the coarse mesh and kept under refinement: no shape recovery
//     (refined vertices stay on the straight coarse edges);
//   - built on each level's own mesh: shape recovery (refined boundary
//     vertices are moved onto the exact boundary by f).

#include <memory>

#include "core/mesh/cell_locator.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

class InterpolatedMap final : public mapping::Map<2> {
 public:
  InterpolatedMap(const Mesh<2>& mesh, const mapping::Map<2>& f);

  void eval(const Points<2>& x0, Points<2>& x) const override;
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override;
  void eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const override;
  std::string describe() const override;

 private:
  std::shared_ptr<const Mesh<2>> mesh_;
  CellLocator locator_;
  Points<2> image_;  ///< f at every mesh vertex
};

}  // namespace warpfem::fem
