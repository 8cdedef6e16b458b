#include "mapping/polygon_sampling.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include "core/threads.hpp"

namespace warpfem::mapping {

bool inside_polygon(const Polygon& polygon, Real x, Real y) {
  const auto& v = polygon.vertices();
  const std::size_t n = v.size();
  bool in = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Real yi = v[i].y(), yj = v[j].y();
    if ((yi > y) != (yj > y)) {
      const Real xc = v[j].x() + (y - yj) * (v[i].x() - v[j].x()) / (yi - yj);
      if (x < xc) in = !in;
    }
  }
  return in;
}

namespace {
Points<2> to_points(const std::vector<Point<2>>& pts) {
  Points<2> out(static_cast<Index>(pts.size()), 2);
  for (std::size_t i = 0; i < pts.size(); ++i) out.row(static_cast<Index>(i)) = pts[i].transpose();
  return out;
}
}  // namespace

Points<2> grid_sample(const Polygon& polygon, int resolution) {
  const Point<2> lo = polygon.bbox_min(), hi = polygon.bbox_max();
  const Point<2> h = (hi - lo) / static_cast<Real>(resolution);
  // Rows tested in parallel (the test costs the polygon's vertex count per point).
  std::vector<char> inside(static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution));
  parallel_for(resolution, 8, [&](Index first, Index last) {
    for (auto j = static_cast<int>(first); j < static_cast<int>(last); ++j)
      for (int i = 0; i < resolution; ++i)
        inside[static_cast<std::size_t>(j) * static_cast<std::size_t>(resolution) +
               static_cast<std::size_t>(i)] =
            inside_polygon(polygon, lo.x() + (i + 0.5) * h.x(), lo.y() + (j + 0.5) * h.y());
  });
  std::vector<Point<2>> pts;
  for (int j = 0; j < resolution; ++j)
    for (int i = 0; i < resolution; ++i)
      if (inside[static_cast<std::size_t>(j) * static_cast<std::size_t>(resolution) +
                 static_cast<std::size_t>(i)])
        pts.emplace_back(lo.x() + (i + 0.5) * h.x(), lo.y() + (j + 0.5) * h.y());
  return to_points(pts);
}

CornerWedge corner_wedge(const Polygon& polygon, Index i) {
  const Point<2> e = polygon.vertex(i + 1) - polygon.vertex(i), f = polygon.vertex(i - 1) - polygon.vertex(i);
  CornerWedge w;
  w.start = std::atan2(e.y(), e.x());
  w.angle = std::atan2(f.y(), f.x()) - w.start;
  while (w.angle <= 0) w.angle += 2 * std::numbers::pi;
  return w;
}

Points<2> boundary_cluster_sample(const Polygon& polygon, int per_edge, int levels) {
  // Next to a vertex J_f depends on the direction; a fold there can occupy a
  // narrow wedge of directions (5 angles missed one of about 10° at the
  // re-entrant corner of a bent L), so the wedge gets 23 directions.
  constexpr int kCornerAngles = 23;
  std::vector<Point<2>> candidates;
  const Index n = polygon.size();
  auto keep = [&](const Point<2>& p) { candidates.push_back(p); };
  for (Index i = 0; i < n; ++i) {
    const Point<2> a = polygon.vertex(i), b = polygon.vertex(i + 1), c = polygon.vertex(i - 1);
    const Point<2> e = b - a;
    const Real len = e.norm();
    const Point<2> normal(-e.y() / len, e.x() / len);  // inward for counter-clockwise order
    // toward edge i
    for (int k = 0; k < per_edge; ++k) {
      const Real s = (k + 0.5) / per_edge;
      for (int l = 1; l <= levels; ++l) keep(a + s * e + std::pow(10.0, -l) * len * normal);
    }
    // into corner i: angles across the interior wedge from edge i (to b) counter-clockwise to c
    const CornerWedge wedge = corner_wedge(polygon, i);
    const Real rad = std::min(len, (c - a).norm());
    for (int k = 1; k <= kCornerAngles; ++k) {
      const Real ang = wedge.start + wedge.angle * k / (kCornerAngles + 1.0);
      for (int l = 1; l <= levels; ++l)
        keep(a + std::pow(10.0, -l) * rad * Point<2>(std::cos(ang), std::sin(ang)));
    }
  }
  // Only the points inside (a thin part of the polygon can put a point meant
  // for one edge beyond another).
  const std::vector<int> side = polygon.side_of(candidates);
  std::vector<Point<2>> pts;
  for (std::size_t i = 0; i < candidates.size(); ++i)
    if (side[i] > 0) pts.push_back(candidates[i]);
  return to_points(pts);
}

Points<2> bijectivity_sample(const Polygon& polygon, int resolution) {
  const Points<2> g = grid_sample(polygon, resolution), b = boundary_cluster_sample(polygon);
  Points<2> out(g.rows() + b.rows(), 2);
  out.topRows(g.rows()) = g;
  out.bottomRows(b.rows()) = b;
  return out;
}

}  // namespace warpfem::mapping
