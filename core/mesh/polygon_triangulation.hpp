#pragma once
// Triangles over the vertices of a simple polygon, without added points:
// CGAL's constrained Delaunay triangulation of its edges, kept inside.

#include <array>
#include <vector>

#include "core/types.hpp"

namespace warpfem {

/// Triangles (vertex indices, counter-clockwise) covering the polygon
/// `vertices` (in order) with its own vertices only. Empty when the polygon is
/// not simple or not counter-clockwise (exact predicates decide both).
std::vector<std::array<int, 3>> triangulate_simple_polygon(const std::vector<Point<2>>& vertices);

}  // namespace warpfem
