#include "mapping/source_points.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "mapping/harmonic/boundary_data.hpp"
#include "mapping/polyhedron_map_check.hpp"

namespace warpfem::mapping {
namespace {

/// The point of triangle abc nearest to p (Ericson, Real-Time Collision Detection, 5.1.5).
Point<3> closest_point_on_triangle(const Point<3>& p, const Point<3>& a, const Point<3>& b,
                                   const Point<3>& c) {
  const Point<3> ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Point<3> bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Point<3> cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const Real denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

SourcePointsReport accept_source_points(const Polyhedron& polyhedron, Points<3>& x, const std::string& file) {
  constexpr std::size_t kListed = 10;
  const Real tolerance = kBoundaryTolerance * (polyhedron.bbox_max() - polyhedron.bbox_min()).norm();
  SourcePointsReport report;
  std::vector<std::pair<Index, Real>> outside;
  Index count = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    const Point<3> q = x.row(p).transpose();
    Real distance = std::numeric_limits<Real>::quiet_NaN();
    if (q.allFinite()) {
      if (winding_number(polyhedron, q) > 0.5) continue;
      Point<3> nearest = q;
      distance = std::numeric_limits<Real>::infinity();
      for (const auto& t : polyhedron.triangles()) {
        const Point<3> r = closest_point_on_triangle(q, polyhedron.vertex(t[0]), polyhedron.vertex(t[1]),
                                                     polyhedron.vertex(t[2]));
        if ((r - q).norm() < distance) distance = (r - q).norm(), nearest = r;
      }
      if (distance <= tolerance) {
        x.row(p) = nearest.transpose();
        ++report.snapped;
        continue;
      }
    }
    ++count;
    if (outside.size() < kListed) outside.emplace_back(p, distance);
  }
  if (outside.empty()) return report;
  std::ostringstream what;
  what << std::setprecision(10);
  for (std::size_t k = 0; k < outside.size(); ++k) {
    const auto [p, distance] = outside[k];
    what << (k ? "; " : "") << "point " << p + 1 << " (" << x(p, 0) << ", " << x(p, 1) << ", " << x(p, 2)
         << ") ";
    if (std::isnan(distance))
      what << "is not a finite number";
    else
      what << "lies outside the source polyhedron by " << std::setprecision(3) << distance
           << std::setprecision(10);
  }
  if (count > static_cast<Index>(outside.size()))
    what << " (" << count << " of " << x.rows() << " points are outside; the first " << outside.size()
         << " are listed)";
  std::ostringstream hint;
  hint << "the map is defined on the source polyhedron only; points up to " << std::setprecision(3)
       << tolerance << " (1e-12 of its diameter) outside count as boundary points";
  throw Error(what.str(), {.file = file, .key_path = "", .hint = hint.str()});
}

SourcePointsReport accept_source_points(const Polygon& polygon, Points<2>& x, const std::string& file) {
  constexpr std::size_t kListed = 10;
  const Real tolerance = kBoundaryTolerance * diameter(polygon);
  SourcePointsReport report;
  std::vector<std::pair<Index, Real>> outside;
  Index count = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    const Point<2> q = x.row(p).transpose();
    if (!q.allFinite()) {
      ++count;
      if (outside.size() < kListed) outside.emplace_back(p, std::numeric_limits<Real>::quiet_NaN());
      continue;
    }
    if (polygon.side_of(q) >= 0) continue;
    Real distance = 0;
    const BoundaryPoint at = closest_boundary_point(polygon, q, &distance);
    if (distance <= tolerance) {
      x.row(p) = boundary_position(polygon, at).transpose();
      ++report.snapped;
      continue;
    }
    ++count;
    if (outside.size() < kListed) outside.emplace_back(p, distance);
  }
  if (outside.empty()) return report;
  std::ostringstream what;
  what << std::setprecision(10);
  for (std::size_t k = 0; k < outside.size(); ++k) {
    const auto [p, distance] = outside[k];
    what << (k ? "; " : "") << "point " << p + 1 << " (" << x(p, 0) << ", " << x(p, 1) << ") ";
    if (std::isnan(distance))
      what << "is not a finite number";
    else
      what << "lies outside the source polygon by " << std::setprecision(3) << distance
           << std::setprecision(10);
  }
  if (count > static_cast<Index>(outside.size()))
    what << " (" << count << " of " << x.rows() << " points are outside; the first " << outside.size()
         << " are listed)";
  std::ostringstream hint;
  hint << "the map is defined on the source polygon only; points up to " << std::setprecision(3) << tolerance
       << " (1e-12 of its diameter) outside count as boundary points";
  throw Error(what.str(), {.file = file, .key_path = "", .hint = hint.str()});
}

}  // namespace warpfem::mapping
