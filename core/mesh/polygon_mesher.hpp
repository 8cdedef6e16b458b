#pragma once
// Triangle meshes of a polygon by CGAL's constrained Delaunay refinement.

#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"

namespace warpfem {

struct PolygonMeshOptions {
  /// Upper bound on the edge length of the triangles; <= 0 means "no size bound"
  /// (only the shape criterion and the polygon's own vertices).
  double max_edge_length = 0.0;
  /// CGAL's shape bound B = circumradius / shortest edge; 0.125 is CGAL's
  /// default and corresponds to a minimum angle of about 20.6 degrees.
  double shape_bound = 0.125;
  /// > 0: every polygon edge is first split into ceil(length / this) equal
  /// pieces whose ends are all mesh vertices (a boundary resolved at least as
  /// finely as the interior, e.g. for boundary data sampled at the vertices).
  double max_boundary_edge_length = 0.0;
};

/// Meshes the (validated) polygon. Every polygon vertex is a mesh vertex and
/// every boundary facet is tagged with the polygon edge it lies on.
/// `interior_points` (strictly inside the polygon) become vertices too, inserted before the refinement.
Mesh<2> mesh_polygon(const Polygon& polygon, const PolygonMeshOptions& options = {},
                     const std::vector<Point<2>>& interior_points = {});

}  // namespace warpfem
