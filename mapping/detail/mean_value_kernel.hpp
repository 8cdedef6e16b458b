#pragma once
// Internal: the vectorized mean value kernel shared by the coordinate API and the maps.
//
// For a block of up to kBlock points it walks once around the polygon. At each
// edge [v_i, v_{i+1}] and every point x it forms s_i = v_i − x, r_i = |s_i| and
//   t_i = tan(α_i/2) = (s_i × s_{i+1}) / (r_i r_{i+1} + s_i·s_{i+1})      if s_i·s_{i+1} ≥ 0
//       = (r_i r_{i+1} − s_i·s_{i+1}) / (s_i × s_{i+1})                  otherwise,
// the branch (a blend, not a jump) avoiding the cancellation of the first form
// near α = π, i.e. next to the edge. With ∇_x α_i = s_{i+1}^⊥/r_{i+1}² − s_i^⊥/r_i²
// (s^⊥ = (s_y, −s_x)) the gradient is ∇t_i = ½(1 + t_i²) ∇α_i, and
//   w_i = (t_{i−1} + t_i) / r_i,   ∇w_i = (∇t_{i−1} + ∇t_i + w_i s_i / r_i) / r_i.
// The inner loops run over the points of the block (structure-of-arrays), so
// the compiler vectorizes them; per point and vertex there is one sqrt and one
// division (1/(r² d) gives both 1/r² and 1/d).
//
// Points for which this is inaccurate or undefined — |t_i| > kMaxTan (closer
// than ~1e-4 relative to an edge, or on it) or closer than kNearVertex·scale to
// a vertex — are flagged; callers re-evaluate them one at a time with the robust
// formula in mean_value_coordinates.cpp.

#include <cmath>

#if defined(__clang__)
#define WARPFEM_IVDEP _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define WARPFEM_IVDEP _Pragma("GCC ivdep")
#else
#define WARPFEM_IVDEP
#endif

// The kernels are forced inline so that they are compiled with the instruction
// set of their caller (barycentric_step.cpp builds AVX2/AVX-512 clones of it).
#if defined(__GNUC__)
#define WARPFEM_KERNEL_INLINE inline __attribute__((always_inline))
#else
#define WARPFEM_KERNEL_INLINE inline
#endif

// Runtime dispatch for the functions that run the kernels: GCC compiles them for
// generic x86-64, x86-64-v3 (AVX2 + FMA) and x86-64-v4 (AVX-512) and picks the
// best at load time by CPU features, so the default (portable) build runs
// vectorized code where the CPU has it. A WARPFEM_NATIVE build compiles once.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__AVX2__)
#define WARPFEM_KERNEL_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#else
#define WARPFEM_KERNEL_CLONES
#endif

namespace warpfem::mapping::detail {

inline constexpr int kBlock = 64;
inline constexpr double kMaxTan = 1e4;
inline constexpr double kNearVertex = 1e-5;

/// Per-block state: the current vertex (s, r, 1/r²), the previous edge's t and ∇t,
/// a robustness flag, and accumulators for the sinks (all distinct arrays, so
/// the vectorizer needs no alias checks).
struct MeanValueScratch {
  alignas(64) double sx[kBlock], sy[kBlock], r[kBlock], ir2[kBlock];
  alignas(64) double tp[kBlock], gtpx[kBlock], gtpy[kBlock];
  alignas(64) double flag[kBlock];
  // accumulators: W, ∇W, Σ w u, Σ u ⊗ ∇w
  alignas(64) double W[kBlock], Wx[kBlock], Wy[kBlock];
  alignas(64) double Fx[kBlock], Fy[kBlock];
  alignas(64) double Gxx[kBlock], Gxy[kBlock], Gyx[kBlock], Gyy[kBlock];
};

/// One edge [v_i, v_{i+1} = (ax, ay)] for all points of the block: t_i, ∇t_i and,
/// if kEmit, the weight of vertex i. Then the state moves on to vertex i+1.
template <bool kGrad, bool kEmit, class Sink>
WARPFEM_KERNEL_INLINE void edge_pass(double ax, double ay, int i, const double* __restrict px,
                                     const double* __restrict py, int cnt, double rtol, MeanValueScratch& s,
                                     Sink& sink) {
  WARPFEM_IVDEP
  for (int p = 0; p < cnt; ++p) {
    const double sxn = ax - px[p], syn = ay - py[p];
    const double r2n = sxn * sxn + syn * syn;
    const double rn = std::sqrt(r2n);
    const double sxc = s.sx[p], syc = s.sy[p], rc = s.r[p], ir2c = s.ir2[p];
    const double cr = sxc * syn - syc * sxn;
    const double dt = sxc * sxn + syc * syn;
    const double rr = rc * rn;
    const bool pos = dt >= 0.0;
    const double num = pos ? cr : rr - dt;
    const double den = pos ? rr + dt : cr;
    const double q = 1.0 / (r2n * den);
    const double ir2n = den * q;
    const double t = num * r2n * q;
    double gtx = 0.0, gty = 0.0;
    if constexpr (kGrad) {
      const double h = 0.5 + 0.5 * t * t;
      gtx = h * (syn * ir2n - syc * ir2c);
      gty = h * (sxc * ir2c - sxn * ir2n);
    }
    if constexpr (kEmit) {
      const double irc = rc * ir2c;
      const double w = (s.tp[p] + t) * irc;
      if constexpr (kGrad) {
        const double c = w * irc;
        sink(i, p, w, (s.gtpx[p] + gtx + c * sxc) * irc, (s.gtpy[p] + gty + c * syc) * irc);
      } else {
        sink(i, p, w, 0.0, 0.0);
      }
    }
    const bool ok = std::abs(t) <= kMaxTan && rn >= rtol;
    s.flag[p] = ok ? s.flag[p] : 1.0;
    s.sx[p] = sxn;
    s.sy[p] = syn;
    s.r[p] = rn;
    s.ir2[p] = ir2n;
    s.tp[p] = t;
    if constexpr (kGrad) {
      s.gtpx[p] = gtx;
      s.gtpy[p] = gty;
    }
  }
}

/// Runs the kernel for `cnt` ≤ kBlock points (px, py) on the polygon (vx, vy, n vertices)
/// and calls sink(i, p, w_i, ∂x w_i, ∂y w_i) for every vertex i and point p
/// (gradients are 0 when kGrad is false). Afterwards s.flag[p] != 0 marks points
/// that need the robust path. `rtol` is the near-vertex distance.
template <bool kGrad, class Sink>
WARPFEM_KERNEL_INLINE void mean_value_block(const double* vx, const double* vy, int n,
                                            const double* __restrict px, const double* __restrict py, int cnt,
                                            double rtol, MeanValueScratch& s, Sink&& sink) {
  // Start at vertex n−1 and take the edge (n−1 → 0) to get t_{n−1} for w_0.
  {
    const double ax = vx[n - 1], ay = vy[n - 1];
    WARPFEM_IVDEP
    for (int p = 0; p < cnt; ++p) {
      const double sx = ax - px[p], sy = ay - py[p];
      const double r2 = sx * sx + sy * sy;
      s.sx[p] = sx;
      s.sy[p] = sy;
      s.r[p] = std::sqrt(r2);
      s.ir2[p] = 1.0 / r2;
      s.flag[p] = s.r[p] >= rtol ? 0.0 : 1.0;
    }
  }
  edge_pass<kGrad, false>(vx[0], vy[0], -1, px, py, cnt, rtol, s, sink);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1 == n) ? 0 : i + 1;
    edge_pass<kGrad, true>(vx[j], vy[j], i, px, py, cnt, rtol, s, sink);
  }
}

}  // namespace warpfem::mapping::detail
