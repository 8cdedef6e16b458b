#include "core/polygon.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/error.hpp"
#include "core/threads.hpp"

namespace warpfem {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KPoint = Kernel::Point_2;
using KSegment = Kernel::Segment_2;

KPoint to_cgal(const Point<2>& p) {
  return KPoint(p.x(), p.y());
}

// Limits of validate(). The mesher's in-circle predicates take fourth powers
// of coordinate differences, which stay far from overflow below 1e30; below
// the size limits (absolute, and relative to the largest coordinate) the
// vertices are barely distinct doubles and areas underflow.
constexpr double kMaxCoordinate = 1e30;
constexpr double kMinExtent = 1e-30;
constexpr double kMinRelativeExtent = 1e-9;
constexpr double kMinRelativeArea = 1e-12;  ///< |signed area| / squared bounding-box size
/// Shortest edge / bounding-box size: below it the coordinates' differences
/// underflow in the maps' products (a 1e-309 edge beside a unit edge turns a
/// mean value weight into inf).
constexpr double kMinRelativeEdge = 1e-9;

/// %g keeps tiny and huge values readable (std::to_string prints 1e-300 as 0.000000).
std::string number_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

std::string vertex_text(const Point<2>& p) {
  return "(" + number_text(p.x()) + ", " + number_text(p.y()) + ")";
}
}  // namespace

Polygon::Polygon(std::vector<Point<2>> vertices, std::string name)
    : vertices_(std::move(vertices)), name_(std::move(name)) {}

Polygon Polygon::checked(std::vector<Point<2>> vertices, std::string name) {
  Polygon p(std::move(vertices), std::move(name));
  p.validate();
  return p;
}

void Polygon::validate() const {
  const Index n = size();
  if (n < 3)
    throw Error(name_ + " has " + std::to_string(n) + " vertices",
                {.file = "", .key_path = "", .hint = "a polygon needs at least 3 vertices"});
  for (Index i = 0; i < n; ++i) {
    if (!vertex(i).allFinite())
      throw Error(name_ + ": vertex " + std::to_string(i) + " is not a finite number",
                  {.file = "", .key_path = "", .hint = "give finite coordinates"});
    if (vertex(i).cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw Error(
          name_ + ": vertex " + std::to_string(i) + " " + vertex_text(vertex(i)) +
              " lies beyond the supported coordinate range |x|, |y| <= " + number_text(kMaxCoordinate),
          {.file = "", .key_path = "", .hint = "rescale the polygon (choose other length units)"});
  }
  // Meshing and the maps take squares and products of coordinate differences:
  // a polygon must be resolvable in double precision and its area representable.
  const Point<2> extent = bbox_max() - bbox_min();
  const double size = extent.maxCoeff();
  const double magnitude = std::max(bbox_max().cwiseAbs().maxCoeff(), bbox_min().cwiseAbs().maxCoeff());
  if (size < kMinExtent || size < kMinRelativeExtent * magnitude)
    throw Error(name_ + " is degenerate or too small: its bounding box is " + number_text(extent.x()) +
                    " x " + number_text(extent.y()) + " at coordinates up to " + number_text(magnitude),
                {.file = "",
                 .key_path = "",
                 .hint = "the polygon's size must be at least " + number_text(kMinExtent) + " and at least " +
                         number_text(kMinRelativeExtent) +
                         " times its largest coordinate; rescale or move it nearer the origin"});
  for (Index i = 0; i < n; ++i) {
    const std::string edge = "edge " + std::to_string(i) + " (vertices " + std::to_string(i) + " and " +
                             std::to_string(wrap(i + 1)) + ")";
    if (to_cgal(vertex(i)) == to_cgal(vertex(i + 1)))
      throw Error(name_ + ": " + edge + " has zero length at " + vertex_text(vertex(i)),
                  {.file = "", .key_path = "", .hint = "remove the duplicated vertex"});
    const double length = (vertex(i + 1) - vertex(i)).norm();
    if (length < kMinRelativeEdge * size)
      throw Error(name_ + ": " + edge + " at " + vertex_text(vertex(i)) + " has length " +
                      number_text(length) + ", below " + number_text(kMinRelativeEdge) +
                      " × the bounding-box size " + number_text(size),
                  {.file = "", .key_path = "", .hint = "merge the two nearly coincident vertices"});
  }
  // Self-intersection: non-adjacent edges must not meet; adjacent edges may
  // only share their common vertex (no fold-back along a line).
  std::vector<KSegment> seg(static_cast<std::size_t>(n));
  std::vector<CGAL::Bbox_2> box(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    seg[i] = KSegment(to_cgal(vertex(i)), to_cgal(vertex(i + 1)));
    box[i] = seg[i].bbox();
  }
  // Sweep over edges sorted by xmin to keep this near O(n log n) in practice.
  std::vector<Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Index{0});
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return box[a].xmin() < box[b].xmin(); });
  for (std::size_t a = 0; a < order.size(); ++a) {
    const Index i = order[a];
    for (std::size_t b = a + 1; b < order.size() && box[order[b]].xmin() <= box[i].xmax(); ++b) {
      const Index j = order[b];
      if (!CGAL::do_overlap(box[i], box[j])) continue;
      const bool adjacent = wrap(i + 1) == j || wrap(j + 1) == i;
      bool bad = false;
      if (!adjacent) {
        bad = CGAL::do_intersect(seg[i], seg[j]);
      } else {
        // Adjacent edges share one vertex; they are bad if they fold back onto each other.
        const Index first = (wrap(i + 1) == j) ? i : j;  // edge first -> shared vertex -> edge second
        const KPoint& p = seg[first].source();
        const KPoint& q = seg[first].target();
        const KPoint& r = seg[wrap(first + 1)].target();
        bad = CGAL::collinear(p, q, r) && !CGAL::collinear_are_ordered_along_line(p, q, r);
        if (n == 3) bad = bad || CGAL::collinear(p, q, r);
      }
      if (bad)
        throw Error(name_ + " is not simple: edge " + std::to_string(std::min(i, j)) + " and edge " +
                        std::to_string(std::max(i, j)) + " intersect",
                    {.file = "",
                     .key_path = "",
                     .hint = "move the vertices so that edges meet only at their shared endpoints"});
    }
  }
  const double area = signed_area();
  if (area == 0 || std::abs(area) < kMinRelativeArea * size * size)
    throw Error(name_ + " is degenerate: signed area " + number_text(area) + " for a bounding box of " +
                    number_text(extent.x()) + " x " + number_text(extent.y()),
                {.file = "", .key_path = "", .hint = "give a polygon that encloses an area"});
  if (area < 0)
    throw Error(
        name_ + " is oriented clockwise (signed area " + number_text(area) + ")",
        {.file = "", .key_path = "", .hint = "reverse the vertex order to make it counter-clockwise"});
}

bool Polygon::is_convex() const {
  const Index n = size();
  for (Index i = 0; i < n; ++i)
    if (CGAL::orientation(to_cgal(vertex(i - 1)), to_cgal(vertex(i)), to_cgal(vertex(i + 1))) ==
        CGAL::RIGHT_TURN)
      return false;
  return true;
}

Real Polygon::signed_area() const {
  Real a = 0;
  for (Index i = 0; i < size(); ++i) {
    const Point<2>& p = vertex(i);
    const Point<2>& q = vertex(i + 1);
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

Real Polygon::perimeter() const {
  Real l = 0;
  for (Index i = 0; i < size(); ++i) l += (vertex(i + 1) - vertex(i)).norm();
  return l;
}

Point<2> Polygon::bbox_min() const {
  Point<2> m = vertices_.front();
  for (const auto& v : vertices_) m = m.cwiseMin(v);
  return m;
}

Point<2> Polygon::bbox_max() const {
  Point<2> m = vertices_.front();
  for (const auto& v : vertices_) m = m.cwiseMax(v);
  return m;
}

namespace {
/// -1 outside, 0 on the boundary, +1 inside the polygon with vertices `pts`.
int bounded_side(const std::vector<KPoint>& pts, const Point<2>& p) {
  switch (CGAL::bounded_side_2(pts.begin(), pts.end(), to_cgal(p), Kernel())) {
    case CGAL::ON_BOUNDED_SIDE: return 1;
    case CGAL::ON_BOUNDARY: return 0;
    default: return -1;
  }
}
std::vector<KPoint> cgal_points(const std::vector<Point<2>>& vertices) {
  std::vector<KPoint> pts;
  pts.reserve(vertices.size());
  for (const auto& v : vertices) pts.push_back(to_cgal(v));
  return pts;
}
}  // namespace

int Polygon::side_of(const Point<2>& p) const {
  return bounded_side(cgal_points(vertices_), p);
}

std::vector<int> Polygon::side_of(const std::vector<Point<2>>& points) const {
  const std::vector<KPoint> pts = cgal_points(vertices_);
  std::vector<int> out(points.size());
  parallel_for(static_cast<Index>(points.size()), 256, [&](Index first, Index last) {
    for (auto i = static_cast<std::size_t>(first); i < static_cast<std::size_t>(last); ++i)
      out[i] = bounded_side(pts, points[i]);
  });
  return out;
}

Polygon Polygon::reversed() const {
  std::vector<Point<2>> v;
  v.reserve(vertices_.size());
  v.push_back(vertices_.front());
  for (auto it = vertices_.rbegin(); it + 1 != vertices_.rend(); ++it) v.push_back(*it);
  return Polygon(std::move(v), name_);
}

void require_same_vertex_count(const Polygon& source, const Polygon& target) {
  if (source.size() != target.size())
    throw Error(source.name() + " has " + std::to_string(source.size()) + " vertices but " + target.name() +
                    " has " + std::to_string(target.size()),
                {.file = "",
                 .key_path = "",
                 .hint = "give both polygons the same number of vertices (add collinear vertices along the "
                         "source's edges, one per target vertex)"});
}

}  // namespace warpfem
