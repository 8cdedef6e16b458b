#pragma once
// User points on the source polygon Ω0. A point computed on an edge in floating
// point lies on either side of it by a rounding error, so points within
// kBoundaryTolerance · diameter(Ω0) outside are boundary points: they are moved
// onto the nearest edge. Points farther out are refused, all of them at once
// (up to ten listed with their distances), so one bad point hides no other.

#include <string>

#include "core/polygon.hpp"
#include "core/polyhedron.hpp"
#include "core/types.hpp"

namespace warpfem::mapping {

/// Relative distance (to the bounding-box diagonal) up to which an outside point is on ∂Ω0.
inline constexpr Real kBoundaryTolerance = 1e-12;

struct SourcePointsReport {
  Index snapped = 0;  ///< points moved onto an edge
};

/// Moves the boundary points of `x` onto ∂`polygon`; throws warpfem::Error
/// naming `file` and listing up to ten points that lie farther outside.
SourcePointsReport accept_source_points(const Polygon& polygon, Points<2>& x, const std::string& file);

/// The same for a polyhedron: points outside by up to kBoundaryTolerance ·
/// diameter are moved onto the nearest triangle.
SourcePointsReport accept_source_points(const Polyhedron& polyhedron, Points<3>& x, const std::string& file);

}  // namespace warpfem::mapping
