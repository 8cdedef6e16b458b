#pragma once
// Sample points inside a polygon, used to check det J_f > 0 (bijectivity).
//
// A regular grid alone misses the places where folds start: next to the
// vertices and edges. bijectivity_sample() therefore adds points clustered
// geometrically toward every edge (distances 10^-1 … 10^-6 of the edge length)
// and into every corner (radii 10^-1 … 10^-6 of the shorter adjacent edge,
// 23 directions across the interior wedge). Only points strictly inside are kept.

#include "core/polygon.hpp"
#include "core/types.hpp"

namespace warpfem::mapping {

/// The interior wedge at vertex i: directions start … start + angle (radians,
/// counter-clockwise from edge i towards edge i − 1; angle in (0, 2π)).
struct CornerWedge {
  Real start = 0;
  Real angle = 0;
};
CornerWedge corner_wedge(const Polygon& polygon, Index i);

/// Even-odd crossing test, fast, for batches; boundary points may go either way.
bool inside_polygon(const Polygon& polygon, Real x, Real y);

/// Cell centres of a resolution x resolution grid over the bounding box, inside only.
Points<2> grid_sample(const Polygon& polygon, int resolution);

/// Points clustered toward every edge and vertex (exact inside test).
Points<2> boundary_cluster_sample(const Polygon& polygon, int per_edge = 8, int levels = 6);

/// grid_sample(resolution) followed by boundary_cluster_sample().
Points<2> bijectivity_sample(const Polygon& polygon, int resolution);

}  // namespace warpfem::mapping
