#pragma once
// An independent fold check for the tests: tiny positively oriented triangles
// clustered toward every vertex and edge of Ω0 (and on a coarse grid) are
// mapped through the public Map API, f only, and the orientation of their
// images is tested. It does not use the program's own det J_f or its sample.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/polygon.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping::test {

struct ProbeSet {
  Points<2> corners;  ///< 3 rows per probe triangle, counter-clockwise
  std::vector<Point<2>> centres;
  std::vector<Real> radii;  ///< circumradius of each triangle
  Real floor = 0;           ///< smallest circumradius still resolved in floating point
  Index triangles() const { return corners.rows() / 3; }
};

/// Counter-clockwise triangle of circumradius r around c.
inline void add_triangle(std::vector<Point<2>>& corners, const Point<2>& c, Real r) {
  for (int k = 0; k < 3; ++k) {
    const Real t = 0.3 + 2 * std::numbers::pi * k / 3;
    corners.emplace_back(c + r * Point<2>(std::cos(t), std::sin(t)));
  }
}

inline Points<2> to_rows(const std::vector<Point<2>>& v) {
  Points<2> out(static_cast<Index>(v.size()), 2);
  for (std::size_t k = 0; k < v.size(); ++k) out.row(static_cast<Index>(k)) = v[k].transpose();
  return out;
}

/// Signed area of the image of each corner triple over its circumradius² (NaN
/// if not finite): about (3√3/4) det J_f for a triangle small enough.
inline std::vector<Real> image_areas(const Map<2>& f, const Points<2>& corners,
                                     const std::vector<Real>& radii) {
  Points<2> y;
  f.eval(corners, y);
  std::vector<Real> area(radii.size());
  for (std::size_t t = 0; t < radii.size(); ++t) {
    const Index k = static_cast<Index>(3 * t);
    const Point<2> a = y.row(k).transpose(), b = y.row(k + 1).transpose(), c = y.row(k + 2).transpose();
    area[t] = ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x()) / (radii[t] * radii[t]);
  }
  return area;
}

/// Probe centres: 0.31 … 3e-6 of the edge length inside each edge (11 places
/// along it), into every corner (radii 0.2 … 2e-6 of the shorter edge, 9
/// directions across the wedge), and a 17 x 17 grid. Each triangle has a
/// circumradius of 1e-3 of its centre's distance to the boundary: it lies inside,
/// and f is close enough to linear across it that its image's orientation is
/// the sign of det J_f.
inline ProbeSet fold_probes(const Polygon& P) {
  std::vector<Point<2>> centres;
  const Index n = P.size();
  auto edge_normal = [&](Index i) {
    const Point<2> e = P.vertex(i + 1) - P.vertex(i);
    return Point<2>(-e.y(), e.x()).normalized();
  };
  for (Index i = 0; i < n; ++i) {
    const Point<2> a = P.vertex(i), e = P.vertex(i + 1) - a;
    for (int k = 0; k < 11; ++k)
      for (Real d = 0.31; d > 2e-6; d /= 7.3)
        centres.push_back(a + (k + 0.43) / 11.0 * e + d * e.norm() * edge_normal(i));
  }
  for (Index i = 0; i < n; ++i) {
    const Point<2> v = P.vertex(i), a = P.vertex(i + 1) - v, b = P.vertex(i - 1) - v;
    const Real start = std::atan2(a.y(), a.x());
    Real wedge = std::atan2(b.y(), b.x()) - start;
    while (wedge <= 0) wedge += 2 * std::numbers::pi;
    const Real r0 = std::min(a.norm(), b.norm());
    for (int k = 1; k <= 9; ++k)
      for (Real r = 0.2; r > 1.5e-6; r /= 6.1) {
        const Real t = start + wedge * k / 10.0;
        centres.emplace_back(v + r * r0 * Point<2>(std::cos(t), std::sin(t)));
      }
  }
  const Point<2> lo = P.bbox_min(), hi = P.bbox_max();
  for (int i = 0; i < 17; ++i)
    for (int j = 0; j < 17; ++j)
      centres.emplace_back(lo.x() + (i + 0.5) / 17 * (hi.x() - lo.x()),
                           lo.y() + (j + 0.5) / 17 * (hi.y() - lo.y()));

  auto boundary_distance = [&](const Point<2>& q) {
    Real d = std::numeric_limits<Real>::infinity();
    for (Index i = 0; i < n; ++i) {
      const Point<2> a = P.vertex(i), e = P.vertex(i + 1) - a;
      const Real t = std::clamp((q - a).dot(e) / e.squaredNorm(), Real{0}, Real{1});
      d = std::min(d, (a + t * e - q).norm());
    }
    return d;
  };
  ProbeSet probes;
  std::vector<Point<2>> corners;
  for (const Point<2>& c : centres) {
    if (P.side_of(c) <= 0) continue;
    const Real r = 1e-3 * boundary_distance(c);
    if (!(r > 1e-9 * (hi - lo).norm())) continue;  // too close to the boundary to be resolved
    probes.centres.push_back(c);
    probes.radii.push_back(r);
    add_triangle(corners, c, r);
  }
  probes.corners = to_rows(corners);
  probes.floor = 1e-11 * (hi - lo).norm();
  return probes;
}

struct ProbeResult {
  Index folded = 0;      ///< image flipped at every scale, its scaled area not tending to 0
  Index unresolved = 0;  ///< flipped down to the floor, but its scaled area still tends to 0
};

/// Probe triangles whose image under f is not counter-clockwise. A strongly
/// curved, strongly anisotropic f can flip the corners' triangle without
/// folding; then the scaled image area tends to (3√3/4) det J_f > 0 as the
/// triangle shrinks (it shrinks by 10 per round, down to probes.floor). A fold
/// keeps a negative scaled area that does not tend to 0. f.eval may throw
/// warpfem::Error (a refused evaluation).
inline ProbeResult flipped_probes(const Map<2>& f, const ProbeSet& probes) {
  std::vector<Real> area = image_areas(f, probes.corners, probes.radii);
  std::vector<Index> suspects;
  std::vector<Real> last;
  for (Index t = 0; t < probes.triangles(); ++t)
    if (!(area[static_cast<std::size_t>(t)] > 0)) {
      suspects.push_back(t);
      last.push_back(area[static_cast<std::size_t>(t)]);
    }
  ProbeResult result;
  std::vector<Real> previous(last.size(), std::numeric_limits<Real>::quiet_NaN());
  for (Real shrink = 0.1; !suspects.empty(); shrink *= 0.1) {
    std::vector<Index> next;
    std::vector<Real> next_last, next_previous, radii;
    std::vector<Point<2>> corners;
    for (std::size_t k = 0; k < suspects.size(); ++k) {
      const Index t = suspects[k];
      const Real r = shrink * probes.radii[static_cast<std::size_t>(t)];
      if (r < probes.floor) {  // judge by the trend of the last two scales
        if (!(std::abs(last[k]) < 0.5 * std::abs(previous[k])))
          ++result.folded;
        else
          ++result.unresolved;
        continue;
      }
      next.push_back(t);
      next_previous.push_back(last[k]);
      radii.push_back(r);
      add_triangle(corners, probes.centres[static_cast<std::size_t>(t)], r);
    }
    if (next.empty()) break;
    area = image_areas(f, to_rows(corners), radii);
    suspects.clear();
    last.clear();
    previous.clear();
    for (std::size_t k = 0; k < next.size(); ++k)
      if (!(area[k] > 0)) {
        suspects.push_back(next[k]);
        last.push_back(area[k]);
        previous.push_back(next_previous[k]);
      }
  }
  return result;
}

}  // namespace warpfem::mapping::test
