#include "mapping/mean_value_coordinates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mapping/detail/mean_value_avx512.hpp"
#include "mapping/detail/mean_value_kernel.hpp"
#include "mapping/detail/nudge_inside.hpp"

namespace warpfem::mapping {
namespace {

/// Below this distance, relative to the shorter edge at the vertex, a point is
/// the vertex. Relative to the local edges (not the whole polygon) so that one
/// far-away vertex does not make small features snap.
constexpr Real kSnap = 1e-13;

Real shorter_edge_at(const PolygonArrays& P, Index j) {
  const Index n = P.size();
  const Index jn = (j + 1) % n, jp = (j + n - 1) % n;
  return std::min(std::hypot(P.x[jn] - P.x[j], P.y[jn] - P.y[j]),
                  std::hypot(P.x[jp] - P.x[j], P.y[jp] - P.y[j]));
}

/// Normalizes scaled weights w̃ (with gradients) into φ, ∇φ. The dominant weight
/// d is treated apart, ∇φ_d = (S ∇w̃_d − w̃_d ∇S)/W², S = Σ_{k≠d} w̃_k, which avoids
/// the cancellation of (1 − φ_d)∇w̃_d when w̃_d carries a large gradient.
void normalize(Index n, const Real* w, const Real* gx, const Real* gy, Real* phi, Real* dx, Real* dy) {
  Index d = 0;
  for (Index k = 1; k < n; ++k)
    if (std::abs(w[k]) > std::abs(w[d])) d = k;
  Real S = 0, Sx = 0, Sy = 0;
  for (Index k = 0; k < n; ++k) {
    if (k == d) continue;
    S += w[k];
    if (dx) {
      Sx += gx[k];
      Sy += gy[k];
    }
  }
  const Real W = S + w[d], iW = 1 / W;
  for (Index k = 0; k < n; ++k) phi[k] = w[k] * iW;
  if (!dx) return;
  const Real Wx = Sx + gx[d], Wy = Sy + gy[d];
  for (Index k = 0; k < n; ++k) {
    dx[k] = (gx[k] - phi[k] * Wx) * iW;
    dy[k] = (gy[k] - phi[k] * Wy) * iW;
  }
  dx[d] = (S * gx[d] - w[d] * Sx) * iW * iW;
  dy[d] = (S * gy[d] - w[d] * Sy) * iW * iW;
}

/// The robust formula at a point that is not a vertex (r_j > 0 for every j).
void off_vertex_coordinates(const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx, Real* dy,
                            std::vector<Real>& work);

}  // namespace

void mean_value_coordinates_at(const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx, Real* dy,
                               std::vector<Real>& work) {
  const Index n = P.size();
  Index j = 0;
  Real rj = std::numeric_limits<Real>::infinity();
  for (Index k = 0; k < n; ++k) {
    const Real r = std::hypot(P.x[k] - x, P.y[k] - y);
    if (r < rj) j = k, rj = r;
  }
  if (rj <= kSnap * shorter_edge_at(P, j)) {  // at a vertex: Kronecker delta
    if (dx) {
      const Point<2> q = detail::nudge_inside(P, j);
      off_vertex_coordinates(P, q.x(), q.y(), phi, dx, dy, work);
    }
    std::fill(phi, phi + n, Real{0});
    phi[j] = 1;
    return;
  }
  off_vertex_coordinates(P, x, y, phi, dx, dy, work);
}

namespace {

void off_vertex_coordinates(const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx, Real* dy,
                            std::vector<Real>& work) {
  const Index n = P.size();
  work.resize(static_cast<std::size_t>(14 * n));
  Real* sx = work.data();
  Real* sy = sx + n;
  Real* r = sy + n;
  Real* t = r + n;   // tan(α_k/2), may be ±inf exactly on edge k
  Real* ga = t + n;  // ∇α_k, 2n
  Real* tau = ga + 2 * n;
  Real* gtau = tau + n;  // 2n
  Real* w = gtau + 2 * n;
  Real* gw = w + n;  // 2n
  const bool grad = dx != nullptr;

  Index j = 0;
  for (Index k = 0; k < n; ++k) {
    sx[k] = P.x[k] - x;
    sy[k] = P.y[k] - y;
    r[k] = std::hypot(sx[k], sy[k]);
    if (r[k] < r[j]) j = k;
  }
  // Edge quantities, with the stable choice of the tan(α/2) formula.
  Index kstar = 0;
  Real num_star = 0, den_star = 1;
  for (Index k = 0; k < n; ++k) {
    const Index kn = (k + 1 == n) ? 0 : k + 1;
    const Real cr = sx[k] * sy[kn] - sy[k] * sx[kn];
    const Real dt = sx[k] * sx[kn] + sy[k] * sy[kn];
    const Real rr = r[k] * r[kn];
    const bool pos = dt >= 0;
    const Real num = pos ? cr : rr - dt;
    const Real den = pos ? rr + dt : cr;
    t[k] = num / den;
    if (k == 0 || std::abs(t[k]) > std::abs(t[kstar])) {
      kstar = k;
      num_star = num;
      den_star = den;
    }
    ga[2 * k] = sy[kn] / (r[kn] * r[kn]) - sy[k] / (r[k] * r[k]);
    ga[2 * k + 1] = sx[k] / (r[k] * r[k]) - sx[kn] / (r[kn] * r[kn]);
  }
  // Scale all weights by u = 1/t_{k*} (the nearly straight angle) when it is large.
  Real u = 1, gux = 0, guy = 0;
  const bool scaled = std::abs(t[kstar]) > 1;
  if (scaled) {
    u = den_star / num_star;
    const Real h = -0.5 * (1 + u * u);
    gux = h * ga[2 * kstar];
    guy = h * ga[2 * kstar + 1];
  }
  for (Index k = 0; k < n; ++k) {
    if (scaled && k == kstar) {
      tau[k] = 1;
      gtau[2 * k] = gtau[2 * k + 1] = 0;
    } else {
      tau[k] = u * t[k];
      const Real h = 0.5 * (u + tau[k] * t[k]);  // u ½(1 + t²)
      gtau[2 * k] = h * ga[2 * k] + t[k] * gux;
      gtau[2 * k + 1] = h * ga[2 * k + 1] + t[k] * guy;
    }
  }
  // Scale by ρ = r_j as well: w̃_k = (ρ/r_k)(τ_{k−1} + τ_k).
  const Real rho = r[j];
  const Real grx = -sx[j] / rho, gry = -sy[j] / rho;
  for (Index k = 0; k < n; ++k) {
    const Index kp = (k == 0) ? n - 1 : k - 1;
    const Real a = rho / r[k];
    const Real sum = tau[kp] + tau[k];
    w[k] = a * sum;
    if (grad) {
      const Real gax = (grx + a * sx[k] / r[k]) / r[k], gay = (gry + a * sy[k] / r[k]) / r[k];
      gw[k] = gax * sum + a * (gtau[2 * kp] + gtau[2 * k]);
      gw[n + k] = gay * sum + a * (gtau[2 * kp + 1] + gtau[2 * k + 1]);
    }
  }
  normalize(n, w, gw, gw + n, phi, dx, dy);
}

/// Evaluates blocks of points and writes φ (and ∇φ) columns of the output matrices.
template <bool kGrad>
WARPFEM_KERNEL_INLINE void mean_value_batch(const PolygonArrays& P, const Points<2>& x, MatrixX& phi,
                                            MatrixX* dphi_dx, MatrixX* dphi_dy) {
  const Index N = x.rows(), n = P.size();
  phi.resize(N, n);
  if constexpr (kGrad) {
    dphi_dx->resize(N, n);
    dphi_dy->resize(N, n);
  }
  const Real* X = x.data();
  const Real* Y = x.data() + N;
  const Real rtol = detail::kNearVertex * P.scale;
  detail::MeanValueScratch s;
  std::vector<Real> work, rphi(static_cast<std::size_t>(3 * n));
  const auto fix_robust_points = [&](Index p0, int cnt, Real* F, Real* DX, Real* DY, auto&& is_robust) {
    for (int p = 0; p < cnt; ++p) {
      if (!is_robust(p)) continue;
      mean_value_coordinates_at(P, X[p0 + p], Y[p0 + p], rphi.data(), kGrad ? rphi.data() + n : nullptr,
                                kGrad ? rphi.data() + 2 * n : nullptr, work);
      for (Index i = 0; i < n; ++i) {
        F[i * N + p] = rphi[i];
        if constexpr (kGrad) {
          DX[i * N + p] = rphi[n + i];
          DY[i * N + p] = rphi[2 * n + i];
        }
      }
    }
  };
#if defined(WARPFEM_HAVE_AVX512_KERNELS)
  const Index block = detail::avx512_kernels_enabled() ? detail::avx512::kCoordinatesBlock : detail::kBlock;
#else
  const Index block = detail::kBlock;
#endif
  for (Index p0 = 0; p0 < N; p0 += block) {
    const int cnt = static_cast<int>(std::min<Index>(block, N - p0));
    Real* F = phi.data() + p0;
    Real* DX = kGrad ? dphi_dx->data() + p0 : nullptr;
    Real* DY = kGrad ? dphi_dy->data() + p0 : nullptr;
#if defined(WARPFEM_HAVE_AVX512_KERNELS)
    if (detail::avx512_kernels_enabled()) {
      unsigned char robust[detail::avx512::kCoordinatesBlock];
      detail::avx512::coordinates(P.x.data(), P.y.data(), static_cast<int>(n), X + p0, Y + p0, cnt, rtol, F,
                                  DX, DY, static_cast<long>(N), robust);
      fix_robust_points(p0, cnt, F, DX, DY, [&](int p) { return robust[p] != 0; });
      continue;
    }
#endif
    std::fill(s.W, s.W + cnt, 0.0);
    std::fill(s.Wx, s.Wx + cnt, 0.0);
    std::fill(s.Wy, s.Wy + cnt, 0.0);
    detail::mean_value_block<kGrad>(P.x.data(), P.y.data(), static_cast<int>(n), X + p0, Y + p0, cnt, rtol, s,
                                    [&s, F, DX, DY, N](int i, int p, double w, double gx, double gy) {
                                      F[i * N + p] = w;
                                      s.W[p] += w;
                                      if constexpr (kGrad) {
                                        DX[i * N + p] = gx;
                                        DY[i * N + p] = gy;
                                        s.Wx[p] += gx;
                                        s.Wy[p] += gy;
                                      } else {
                                        (void)DX, (void)DY;  // captured for the gradient variant only
                                      }
                                    });
    for (int p = 0; p < cnt; ++p) s.W[p] = 1.0 / s.W[p];
    for (Index i = 0; i < n; ++i) {
      Real* f = F + i * N;
      if constexpr (kGrad) {
        Real* dx = DX + i * N;
        Real* dy = DY + i * N;
        WARPFEM_IVDEP
        for (int p = 0; p < cnt; ++p) {
          const Real ph = f[p] * s.W[p];
          f[p] = ph;
          dx[p] = (dx[p] - ph * s.Wx[p]) * s.W[p];
          dy[p] = (dy[p] - ph * s.Wy[p]) * s.W[p];
        }
      } else {
        WARPFEM_IVDEP
        for (int p = 0; p < cnt; ++p) f[p] *= s.W[p];
      }
    }
    fix_robust_points(p0, cnt, F, DX, DY, [&](int p) { return s.flag[p] != 0.0; });
  }
}

WARPFEM_KERNEL_CLONES void mean_value_values(const PolygonArrays& P, const Points<2>& x, MatrixX& phi) {
  mean_value_batch<false>(P, x, phi, nullptr, nullptr);
}

WARPFEM_KERNEL_CLONES void mean_value_gradients(const PolygonArrays& P, const Points<2>& x, MatrixX& phi,
                                                MatrixX* dphi_dx, MatrixX* dphi_dy) {
  mean_value_batch<true>(P, x, phi, dphi_dx, dphi_dy);
}

}  // namespace

void mean_value_coordinates(const PolygonArrays& polygon, const Points<2>& x, MatrixX& phi) {
  mean_value_values(polygon, x, phi);
}

void mean_value_coordinates(const PolygonArrays& polygon, const Points<2>& x, MatrixX& phi, MatrixX& dphi_dx,
                            MatrixX& dphi_dy) {
  mean_value_gradients(polygon, x, phi, &dphi_dx, &dphi_dy);
}

}  // namespace warpfem::mapping
