#include "mapping/harmonic/intermediate_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "core/error.hpp"

namespace warpfem::mapping {

Polygon regular_polygon(Index n) {
  require(n >= 3, "regular polygon: needs at least 3 vertices");
  std::vector<Point<2>> v;
  for (Index k = 0; k < n; ++k) {
    const Real a = 2 * std::numbers::pi * static_cast<Real>(k) / static_cast<Real>(n);
    v.emplace_back(std::cos(a), std::sin(a));
  }
  return Polygon(v, "regular " + std::to_string(n) + "-gon");
}

Polygon cyclic_polygon(const std::vector<Real>& l) {
  const std::size_t n = l.size();
  require(n >= 3, "cyclic polygon: needs at least 3 edges");
  const std::size_t imax = static_cast<std::size_t>(std::max_element(l.begin(), l.end()) - l.begin());
  const Real lmax = l[imax], sum = std::accumulate(l.begin(), l.end(), Real{0});
  if (!(lmax < sum - lmax) || std::any_of(l.begin(), l.end(), [](Real x) { return !(x > 0); }))
    throw Error("cyclic polygon: every edge must be positive and shorter than the sum of the others");
  auto half_angle = [](Real len, Real R) { return std::asin(std::min(Real{1}, len / (2 * R))); };
  auto others = [&](Real R) {
    Real s = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (i != imax) s += 2 * half_angle(l[i], R);
    return s;
  };
  const Real R0 = lmax / 2;
  // center inside: Σ α_i = 2π; center outside (beyond the longest edge): Σ_{i≠max} α_i = α_max
  const bool inside = others(R0) + std::numbers::pi >= 2 * std::numbers::pi;
  auto g = [&](Real R) {
    return inside ? others(R) + 2 * half_angle(lmax, R) - 2 * std::numbers::pi
                  : others(R) - 2 * half_angle(lmax, R);
  };
  Real lo = R0, hi = R0 * 2;
  if (inside) {
    while (g(hi) > 0) hi *= 2;  // g decreases from ≥ 0
  } else {
    while (g(hi) < 0) hi *= 2;  // g increases from < 0
  }
  for (int it = 0; it < 200; ++it) {
    const Real mid = 0.5 * (lo + hi);
    if ((g(mid) > 0) == inside)
      lo = mid;
    else
      hi = mid;
  }
  const Real R = 0.5 * (lo + hi);
  std::vector<Point<2>> v;
  Real angle = 0;
  for (std::size_t i = 0; i < n; ++i) {
    v.emplace_back(R * std::cos(angle), R * std::sin(angle));
    Real a = 2 * half_angle(l[i], R);
    if (i == imax && !inside) a = 2 * std::numbers::pi - a;
    angle += a;
  }
  return Polygon(v, "cyclic " + std::to_string(n) + "-gon");
}

Polygon cyclic_intermediate(const Polygon& source, const Polygon& target) {
  require_same_vertex_count(source, target);
  std::vector<Real> l;
  const Real ps = source.perimeter(), pt = target.perimeter();
  for (Index i = 0; i < source.size(); ++i)
    l.push_back(0.5 * ((source.vertex(i + 1) - source.vertex(i)).norm() / ps +
                       (target.vertex(i + 1) - target.vertex(i)).norm() / pt));
  return cyclic_polygon(l);
}

bool is_strictly_convex(const std::vector<Point<2>>& v, Real tolerance) {
  const std::size_t n = v.size();
  if (n < 3) return false;
  Real turning = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point<2> a = v[(i + n - 1) % n], b = v[i], c = v[(i + 1) % n];
    const Point<2> e0 = b - a, e1 = c - b;
    const Real cross = e0.x() * e1.y() - e0.y() * e1.x();
    if (!(cross > tolerance * e0.norm() * e1.norm())) return false;
    turning += std::atan2(cross, e0.dot(e1));
  }
  return std::abs(turning - 2 * std::numbers::pi) < 1e-6;
}

}  // namespace warpfem::mapping
