#include "mapping/harmonic/triangle_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace warpfem::mapping {

TriangleLocator::TriangleLocator(const Points<2>& vertices,
                                 const std::vector<std::array<Index, 3>>& triangles)
    : v_(vertices), tri_(triangles) {
  lo_ = v_.colwise().minCoeff().transpose();
  const Point<2> hi = v_.colwise().maxCoeff().transpose();
  const Point<2> ext = (hi - lo_).cwiseMax(1e-300);
  const Real per_side = std::sqrt(static_cast<Real>(std::max<std::size_t>(tri_.size(), 1)));
  const Real aspect = ext.x() / ext.y();
  nx_ = std::clamp(static_cast<int>(per_side * std::sqrt(aspect)), 1, 4096);
  ny_ = std::clamp(static_cast<int>(per_side / std::sqrt(aspect)), 1, 4096);
  cell_ = Point<2>(ext.x() / nx_, ext.y() / ny_) * (1 + 1e-12);
  auto cells_of = [&](Index t, int& i0, int& i1, int& j0, int& j1) {
    Real xmin = std::numeric_limits<Real>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
    for (Index k : tri_[static_cast<std::size_t>(t)]) {
      xmin = std::min(xmin, v_(k, 0));
      xmax = std::max(xmax, v_(k, 0));
      ymin = std::min(ymin, v_(k, 1));
      ymax = std::max(ymax, v_(k, 1));
    }
    i0 = std::clamp(static_cast<int>((xmin - lo_.x()) / cell_.x()), 0, nx_ - 1);
    i1 = std::clamp(static_cast<int>((xmax - lo_.x()) / cell_.x()), 0, nx_ - 1);
    j0 = std::clamp(static_cast<int>((ymin - lo_.y()) / cell_.y()), 0, ny_ - 1);
    j1 = std::clamp(static_cast<int>((ymax - lo_.y()) / cell_.y()), 0, ny_ - 1);
  };
  start_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
  const Index nt = static_cast<Index>(tri_.size());
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<Index> fill(start_.begin(), start_.end() - 1);
    for (Index t = 0; t < nt; ++t) {
      int i0, i1, j0, j1;
      cells_of(t, i0, i1, j0, j1);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const std::size_t c =
              static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i);
          if (pass == 0)
            ++start_[c + 1];
          else
            items_[static_cast<std::size_t>(fill[c]++)] = t;
        }
    }
    if (pass == 0) {
      for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
      items_.resize(static_cast<std::size_t>(start_.back()));
    }
  }
}

std::array<Real, 3> TriangleLocator::barycentric(Index t, const Point<2>& p) const {
  const auto& T = tri_[static_cast<std::size_t>(t)];
  const Real ax = v_(T[0], 0), ay = v_(T[0], 1);
  const Real bx = v_(T[1], 0) - ax, by = v_(T[1], 1) - ay, cx = v_(T[2], 0) - ax, cy = v_(T[2], 1) - ay;
  const Real px = p.x() - ax, py = p.y() - ay;
  const Real det = bx * cy - by * cx;
  const Real l1 = (px * cy - py * cx) / det, l2 = (bx * py - by * px) / det;
  return {1 - l1 - l2, l1, l2};
}

TriangleLocator::Hit TriangleLocator::locate(const Point<2>& p) const {
  Hit best;
  Real best_min = -std::numeric_limits<Real>::infinity();
  const int ci = std::clamp(static_cast<int>(std::floor((p.x() - lo_.x()) / cell_.x())), 0, nx_ - 1);
  const int cj = std::clamp(static_cast<int>(std::floor((p.y() - lo_.y()) / cell_.y())), 0, ny_ - 1);
  const int max_ring = std::max(nx_, ny_);
  for (int ring = 0; ring <= max_ring; ++ring) {
    for (int j = cj - ring; j <= cj + ring; ++j) {
      if (j < 0 || j >= ny_) continue;
      for (int i = ci - ring; i <= ci + ring; ++i) {
        if (i < 0 || i >= nx_) continue;
        if (std::max(std::abs(i - ci), std::abs(j - cj)) != ring) continue;  // only the ring's cells
        const std::size_t c =
            static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i);
        for (Index k = start_[c]; k < start_[c + 1]; ++k) {
          const Index t = items_[static_cast<std::size_t>(k)];
          const auto b = barycentric(t, p);
          const Real m = std::min({b[0], b[1], b[2]});
          if (m > best_min) {
            best_min = m;
            best.triangle = t;
            best.bary = b;
          }
        }
      }
    }
    if (best_min >= -1e-12) break;               // found a containing triangle
    if (best.triangle >= 0 && ring >= 1) break;  // outside: the nearby best is good enough
  }
  best.inside = best_min >= -1e-12;
  if (!best.inside && best.triangle >= 0) {
    Real s = 0;
    for (Real& b : best.bary) s += (b = std::max(b, Real{0}));
    for (Real& b : best.bary) b /= s;
  }
  return best;
}

}  // namespace warpfem::mapping
