#pragma once
// Meshes of simple parametrization domains that do not need a Delaunay mesher:
// structured grids of rectangles and of axis-aligned boxes, and quadrilateral
// meshes of any polygon by splitting each triangle of a triangle mesh into
// three quadrilaterals.

#include <array>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"

namespace warpfem {

/// True if the polygon is an axis-aligned rectangle (possibly with extra
/// collinear vertices along its sides, as parametrization domains carry).
bool is_axis_aligned_rectangle(const Polygon& polygon);

/// nx x ny grid on the polygon's bounding rectangle: quadrilaterals, or two
/// triangles per rectangle. Boundary facets are tagged with the polygon edge
/// containing their midpoint. Throws warpfem::Error if the polygon is not an
/// axis-aligned rectangle.
Mesh<2> structured_mesh(const Polygon& rectangle, int nx, int ny, CellType type);

/// Splits every triangle into three quadrilaterals (corner, two edge
/// midpoints, centroid). Tags carry over to the split boundary facets.
Mesh<2> split_into_quadrilaterals(const Mesh<2>& triangles);

/// Re-tags boundary facets with the polygon edge containing each facet's midpoint.
void tag_boundary_facets(Mesh<2>& mesh, const Polygon& polygon);

/// All edges of cells that belong to only one cell, oriented counter-clockwise.
IndexTable find_boundary_facets(const Mesh<2>& mesh);

/// nx x ny x nz grid of the box [lo, hi]: hexahedra, or six tetrahedra per
/// hexahedron (Kuhn/Freudenthal split along the diagonal from the low to the
/// high corner, conforming because every box is split the same way). Cells
/// are positively oriented. Boundary facets (quadrilaterals or triangles,
/// outward) are tagged with the box face they lie on: 0 x = lo.x, 1 x = hi.x,
/// 2 y = lo.y, 3 y = hi.y, 4 z = lo.z, 5 z = hi.z.
Mesh<3> structured_box_mesh(const Point<3>& lo, const Point<3>& hi, const std::array<int, 3>& cells,
                            CellType type);

/// All facets of cells that belong to only one cell, outward (cell_faces order
/// of their cell), listed by cell then local facet.
IndexTable find_boundary_facets(const Mesh<3>& mesh);

}  // namespace warpfem
