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
WARPFEM_KERNEL_INLINE void normalize(Index n, const Real* w, const Real* gx, const Real* gy, Real* phi,
                                     Real* dx, Real* dy) {
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

/// The robust formula at a point that is not a vertex (r_j > 0 for every j);
/// forced inline, so that it is compiled for the instruction set of
/// mean_value_coordinates_at's clone.
WARPFEM_KERNEL_INLINE void off_vertex_coordinates(const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx,
                                                  Real* dy, std::vector<Real>& work);

}  // namespace

WARPFEM_KERNEL_CLONES void mean_value_coordinates_at(const PolygonArrays& P, Real x, Real y, Real* phi,
                                                     Real* dx, Real* dy, std::vector<Real>& work) {
  const Index n = P.size();
  Index j = 0;
  Real rj2 = std::numeric_limits<Real>::infinity();
  for (Index k = 0; k < n; ++k) {
    const Real ex = P.x[k] - x, ey = P.y[k] - y, r2 = ex * ex + ey * ey;
    if (r2 < rj2) j = k, rj2 = r2;
  }
  if (std::sqrt(rj2) <= kSnap * shorter_edge_at(P, j)) {  // at a vertex: Kronecker delta
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

WARPFEM_KERNEL_INLINE void off_vertex_coordinates(const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx,
                                                  Real* dy, std::vector<Real>& work) {
  // The points that come here are the vectorized kernel's hard ones, next to
  // edges and vertices: a check on points clustered at the boundary of a
  // polygon of many vertices costs what this loop costs. So each pass is a
  // plain loop over the vertices that the compiler vectorizes (the searches
  // for the nearest vertex and the largest tangent are separate passes), with
  // two divisions and one square root per vertex: 1/r² serves ∇α, 1/r and ρ/r.
  const Index n = P.size();
  work.resize(static_cast<std::size_t>(12 * n));
  Real* sx = work.data();
  Real* sy = sx + n;
  Real* r = sy + n;
  Real* ir2 = r + n;  // 1/r²
  Real* t = ir2 + n;  // tan(α_k/2), may be ±inf exactly on edge k; then τ_k
  Real* gax = t + n;  // ∇α_k
  Real* gay = gax + n;
  Real* w = gay + n;
  Real* gw = w + n;        // 2n
  Real* gtx = gw + 2 * n;  // ∇τ_k
  Real* gty = gtx + n;
  const Real* px = P.x.data();
  const Real* py = P.y.data();
  const bool grad = dx != nullptr;

  WARPFEM_IVDEP
  for (Index k = 0; k < n; ++k) {
    sx[k] = px[k] - x;
    sy[k] = py[k] - y;
    const Real r2 = sx[k] * sx[k] + sy[k] * sy[k];
    r[k] = std::sqrt(r2);
    ir2[k] = 1 / r2;
  }
  Index j = 0;
  for (Index k = 1; k < n; ++k)
    if (r[k] < r[j]) j = k;
  // Edge k, from vertex k to vertex kn, with the stable choice of the tan(α/2) formula.
  const auto fraction = [&](Index k, Index kn, Real& num, Real& den) {
    const Real cr = sx[k] * sy[kn] - sy[k] * sx[kn];
    const Real dt = sx[k] * sx[kn] + sy[k] * sy[kn];
    const Real rr = r[k] * r[kn];
    const bool pos = dt >= 0;
    num = pos ? cr : rr - dt;
    den = pos ? rr + dt : cr;
  };
  const auto edge = [&](Index k, Index kn) {
    Real num, den;
    fraction(k, kn, num, den);
    t[k] = num / den;
    gax[k] = sy[kn] * ir2[kn] - sy[k] * ir2[k];
    gay[k] = sx[k] * ir2[k] - sx[kn] * ir2[kn];
  };
  WARPFEM_IVDEP
  for (Index k = 0; k + 1 < n; ++k) edge(k, k + 1);
  edge(n - 1, 0);
  Index kstar = 0;
  for (Index k = 1; k < n; ++k)
    if (std::abs(t[k]) > std::abs(t[kstar])) kstar = k;
  // Scale all weights by u = 1/t_{k*} (the nearly straight angle) when it is large.
  Real u = 1, gux = 0, guy = 0;
  const bool scaled = std::abs(t[kstar]) > 1;
  if (scaled) {
    Real num, den;
    fraction(kstar, kstar + 1 == n ? 0 : kstar + 1, num, den);
    u = den / num;
    const Real h = -0.5 * (1 + u * u);
    gux = h * gax[kstar];
    guy = h * gay[kstar];
  }
  WARPFEM_IVDEP
  for (Index k = 0; k < n; ++k) {
    const Real tk = t[k], tau = u * tk;
    const Real h = 0.5 * (u + tau * tk);  // u ½(1 + t²)
    t[k] = tau;
    gtx[k] = h * gax[k] + tk * gux;
    gty[k] = h * gay[k] + tk * guy;
  }
  if (scaled) t[kstar] = 1, gtx[kstar] = gty[kstar] = 0;
  // Scale by ρ = r_j as well: w̃_k = (ρ/r_k)(τ_{k−1} + τ_k).
  const Real rho = r[j];
  const Real grx = -sx[j] / rho, gry = -sy[j] / rho;
  const auto weight = [&](Index k, Index kp) {
    const Real ir = r[k] * ir2[k];  // 1/r_k
    const Real a = rho * ir;
    const Real sum = t[kp] + t[k];
    w[k] = a * sum;
    if (grad) {
      const Real gax_k = grx * ir + a * sx[k] * ir2[k], gay_k = gry * ir + a * sy[k] * ir2[k];
      gw[k] = gax_k * sum + a * (gtx[kp] + gtx[k]);
      gw[n + k] = gay_k * sum + a * (gty[kp] + gty[k]);
    }
  };
  weight(0, n - 1);
  WARPFEM_IVDEP
  for (Index k = 1; k < n; ++k) weight(k, k - 1);
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
