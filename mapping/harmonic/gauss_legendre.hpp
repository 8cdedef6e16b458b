#pragma once
// Gauss–Legendre rule on [0, 1] (nodes by Newton's method on P_n).

#include <cmath>
#include <numbers>
#include <vector>

#include "core/types.hpp"

namespace warpfem::mapping {

struct QuadratureRule {
  std::vector<Real> s, w;  ///< nodes in (0, 1), weights summing to 1
};

inline QuadratureRule gauss_legendre(int n) {
  QuadratureRule q;
  q.s.resize(static_cast<std::size_t>(n));
  q.w.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    Real x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      Real p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const Real p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1;
      dp = n * (x * p1 - p0) / (x * x - 1);
      const Real dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    q.s[static_cast<std::size_t>(i)] = 0.5 * (1 - x);
    q.w[static_cast<std::size_t>(i)] = 1 / ((1 - x * x) * dp * dp);
  }
  return q;
}

}  // namespace warpfem::mapping
