#include "fem/geometry/mesh_point_locator.hpp"

#include <sstream>

#include "core/error.hpp"

namespace warpfem::fem {

template <int dim>
MeshPointLocator<dim>::MeshPointLocator(const Mesh<dim>& mesh) {
  if constexpr (dim == 2) {
    locator_ = std::make_unique<CellLocator>(mesh);
  } else {
    if (mesh.cell_type != CellType::tetrahedron)
      throw Error(
          "point location between levels (standard-FEM geometry, reference solutions) needs a "
          "tetrahedral mesh in 3D",
          {.file = "", .key_path = "/mesh/cell_type", .hint = "use \"cell_type\": \"tetrahedron\""});
    locator_ = std::make_unique<mapping::TetLocator>(mesh.vertices, mesh.cells);
  }
}

template <int dim>
std::pair<Index, Point<dim>> MeshPointLocator<dim>::locate(const Point<dim>& x0, const char* what) const {
  Index cell = -1;
  Point<dim> xi = Point<dim>::Zero();
  if constexpr (dim == 2) {
    const auto loc = locator_->locate(x0);
    cell = loc.cell;
    xi = loc.xi;
  } else {
    // The reference tetrahedron has corners 0, e1, e2, e3: barycentric coordinates
    // (1 − Σξ, ξ1, ξ2, ξ3). Points a round-off outside every cell are accepted.
    const auto loc = locator_->locate(x0);
    if (loc.cell >= 0 && loc.least() > -1e-9) {
      cell = loc.cell;
      for (int d = 0; d < 3; ++d) xi(d) = loc.barycentric[static_cast<std::size_t>(d + 1)];
    }
  }
  if (cell < 0) {
    std::ostringstream os;
    os << what << ": point (" << x0.transpose() << ") lies outside the mesh";
    throw Error(os.str());
  }
  return {cell, xi};
}

template class MeshPointLocator<2>;
template class MeshPointLocator<3>;

}  // namespace warpfem::fem
