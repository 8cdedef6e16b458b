#pragma once
// Internal: the point a tiny step inside a polygon from one of its vertices,
// where the coordinate kernels take the one-sided gradient at that vertex.

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/types.hpp"
#include "mapping/barycentric_coordinates.hpp"

namespace warpfem::mapping::detail {

/// Gradient at a vertex: the coordinates are only continuous there, so the
/// kernels take the one-sided value from a point a tiny step inside along the
/// interior bisector (the inward normal at a straight corner). The step is far
/// above the rounding of the vertex's coordinates, so the point is never the
/// vertex itself; callers evaluate it with their off-vertex formula, never by
/// recursing into the vertex case (a step below their snap distance would recurse
/// without end).
inline Point<2> nudge_inside(const PolygonArrays& P, Index j) {
  const Index n = P.size();
  const Index jn = (j + 1) % n, jp = (j + n - 1) % n;
  Point<2> v(P.x[j], P.y[j]);
  Point<2> a(P.x[jn] - v.x(), P.y[jn] - v.y()), b(P.x[jp] - v.x(), P.y[jp] - v.y());
  const Real la = a.norm(), lb = b.norm();
  a /= la;
  b /= lb;
  const Real cr = a.x() * b.y() - a.y() * b.x();  // > 0: convex corner (interior angle < π)
  Point<2> d = a + b;
  if (std::abs(cr) < 1e-12 && a.dot(b) < 0) {
    d = Point<2>(-a.y(), a.x());  // straight corner: inward normal
  } else if (cr < 0) {
    d = -d;  // reflex corner: the bisector of the two edges points outside
  }
  const Real ulp_floor = 64 * std::numeric_limits<Real>::epsilon() * v.cwiseAbs().maxCoeff();
  return v + std::max(1e-7 * std::min(la, lb), ulp_floor) * d.normalized();
}

}  // namespace warpfem::mapping::detail
