#pragma once
// Which cell of a mesh of Ω0 holds a point x0, and x0's reference coordinates
// there: for evaluating functions of one level of a nested hierarchy at points
// of another. Triangles and quadrilaterals in 2D, tetrahedra in 3D (a
// hexahedron would need a trilinear inverse per query).

#include <memory>
#include <type_traits>
#include <utility>

#include "core/mesh/cell_locator.hpp"
#include "core/mesh/mesh.hpp"
#include "mapping/harmonic/tet_locator.hpp"

namespace warpfem::fem {

template <int dim>
class MeshPointLocator {
 public:
  /// `mesh` must outlive the locator. Throws warpfem::Error naming `/mesh/cell_type`
  /// for a 3D mesh of other cells than tetrahedra.
  explicit MeshPointLocator(const Mesh<dim>& mesh);

  /// The cell holding x0 and the reference point of x0 in it; throws warpfem::Error
  /// naming `what` when x0 lies outside the mesh (beyond round-off).
  std::pair<Index, Point<dim>> locate(const Point<dim>& x0, const char* what) const;

 private:
  std::unique_ptr<std::conditional_t<dim == 2, CellLocator, mapping::TetLocator>> locator_;
};

}  // namespace warpfem::fem
