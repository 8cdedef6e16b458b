// AVX-512 mean value kernels (see mean_value_avx512.hpp). Compiled with
// -mavx512f; only called after avx512_kernels_enabled() said the CPU has it.
// Deliberately includes no standard library header (see the header).

#include "mapping/detail/mean_value_avx512.hpp"

#include <immintrin.h>

// GCC 12's rsqrt14 intrinsic passes an undefined vector as the (unused)
// merge source, which -Wmaybe-uninitialized reports.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace warpfem::mapping::detail::avx512 {
namespace {

constexpr double kMaxTan = 1e4;  // keep equal to mean_value_kernel.hpp

inline __m512d bcast(double v) {
  return _mm512_set1_pd(v);
}

/// 1/√x: rsqrt14 estimate and two Newton steps y ← y (3/2 − x/2 y²).
inline __m512d rsqrt(__m512d x) {
  const __m512d h = _mm512_mul_pd(x, bcast(0.5));
  __m512d y = _mm512_rsqrt14_pd(x);
  y = _mm512_mul_pd(y, _mm512_fnmadd_pd(_mm512_mul_pd(h, y), y, bcast(1.5)));
  y = _mm512_mul_pd(y, _mm512_fnmadd_pd(_mm512_mul_pd(h, y), y, bcast(1.5)));
  return y;
}

/// s = v − x, |s|² and |s| for one vertex v = (ax, ay) at eight points.
struct Offset {
  __m512d sx, sy, r2, r;
};

/// State at the current vertex i of the walk, for eight points. The walk is
/// skewed by one vertex: while edge [v_i, v_{i+1}] is processed, the square
/// root for v_{i+2} is already issued, so its latency is off the chain (an
/// edge's chain is otherwise ~90 cycles, more than the out-of-order window
/// hides; measured +15-20 % for the map step, +5 % for values + gradients;
/// skewing more deeply runs out of registers and is slower).
struct Walk {
  __m512d px, py;
  __m512d sx, sy, r, irc;  // s_i = v_i − x, |s_i|, 1/|s_i|
  __m512d nx, ny;          // s_i/|s_i|², shared by the gradients of t_{i−1} and t_i
  Offset next;             // v_{i+1}
  __m512d tp, gtpx, gtpy;  // t_{i−1} = tan(α_{i−1}/2) and its gradient
  __mmask8 ok;             // false once a point is too close to an edge or a vertex
  __m512d rtol;

  inline Offset offset(double ax, double ay) const {
    Offset o;
    o.sx = _mm512_sub_pd(bcast(ax), px);
    o.sy = _mm512_sub_pd(bcast(ay), py);
    o.r2 = _mm512_fmadd_pd(o.sx, o.sx, _mm512_mul_pd(o.sy, o.sy));
    o.r = _mm512_sqrt_pd(o.r2);  // the divider unit, in parallel with the FMA pipes
    return o;
  }

  /// Starts at v_i = a; b is v_{i+1}.
  void start(double ax, double ay, double bx, double by) {
    sx = _mm512_sub_pd(bcast(ax), px);
    sy = _mm512_sub_pd(bcast(ay), py);
    const __m512d r2 = _mm512_fmadd_pd(sx, sx, _mm512_mul_pd(sy, sy));
    irc = rsqrt(r2);
    r = _mm512_mul_pd(r2, irc);
    const __m512d ir2 = _mm512_mul_pd(irc, irc);
    nx = _mm512_mul_pd(sx, ir2);
    ny = _mm512_mul_pd(sy, ir2);
    ok = _mm512_cmp_pd_mask(r, rtol, _CMP_GE_OQ);
    next = offset(bx, by);
  }

  /// Edge [v_i, v_{i+1}]: t_i, ∇t_i; with kEmit the weight w_i and ∇w_i go to
  /// emit(w, wx, wy). Then the walk moves on to v_{i+1}; (ax, ay) is v_{i+2}.
  ///
  /// With n_i = s_i/|s_i|²: ∇t_i = (1 + t_i²)/2 · (n_{i+1} − n_i)^⊥ and
  /// ∇w_i = w_i n_i + (∇t_{i−1} + ∇t_i)/|s_i|. Each n_i is computed once and
  /// used by both edges at v_i: 33 instead of 36 multiply-class operations per
  /// edge in the map step, which bound it on the two FMA pipes.
  template <bool kGrad, bool kEmit, bool kTwoDivisions, class Emit>
  inline void edge(double ax, double ay, Emit&& emit) {
    const Offset after = offset(ax, ay);
    const __m512d sxn = next.sx, syn = next.sy, r2n = next.r2, rn = next.r;
    const __m512d cr = _mm512_fmsub_pd(sx, syn, _mm512_mul_pd(sy, sxn));
    const __m512d dt = _mm512_fmadd_pd(sx, sxn, _mm512_mul_pd(sy, syn));
    const __m512d rr = _mm512_mul_pd(r, rn);
    // Stable tan(α/2): cr/(rr + dt) if dt ≥ 0, else (rr − dt)/cr.
    const __mmask8 pos = _mm512_cmp_pd_mask(dt, _mm512_setzero_pd(), _CMP_GE_OQ);
    const __m512d num = _mm512_mask_blend_pd(pos, _mm512_sub_pd(rr, dt), cr);
    const __m512d den = _mm512_mask_blend_pd(pos, cr, _mm512_add_pd(rr, dt));
    // Divisions on the divider unit, beside the square roots, off the FMA pipes.
    // Two (1/|s|² and tan(α/2) directly) where the FMA pipes are the busier
    // unit (the map step's accumulation), else one of |s|²·den followed by
    // three multiplications.
    __m512d ir2n, t;
    if constexpr (kTwoDivisions) {
      ir2n = _mm512_div_pd(bcast(1.0), r2n);
      t = _mm512_div_pd(num, den);
    } else {
      const __m512d q = _mm512_div_pd(bcast(1.0), _mm512_mul_pd(r2n, den));  // 1/(r² den)
      ir2n = _mm512_mul_pd(den, q);
      t = _mm512_mul_pd(_mm512_mul_pd(num, r2n), q);
    }
    __m512d gtx = _mm512_setzero_pd(), gty = _mm512_setzero_pd(), nxn = gtx, nyn = gtx;
    if constexpr (kGrad) {
      nxn = _mm512_mul_pd(sxn, ir2n);
      nyn = _mm512_mul_pd(syn, ir2n);
      const __m512d h = _mm512_fmadd_pd(_mm512_mul_pd(t, t), bcast(0.5), bcast(0.5));
      gtx = _mm512_mul_pd(h, _mm512_sub_pd(nyn, ny));
      gty = _mm512_mul_pd(h, _mm512_sub_pd(nx, nxn));
    }
    if constexpr (kEmit) {
      const __m512d w = _mm512_mul_pd(_mm512_add_pd(tp, t), irc);
      if constexpr (kGrad) {
        const __m512d wx = _mm512_fmadd_pd(w, nx, _mm512_mul_pd(_mm512_add_pd(gtpx, gtx), irc));
        const __m512d wy = _mm512_fmadd_pd(w, ny, _mm512_mul_pd(_mm512_add_pd(gtpy, gty), irc));
        emit(w, wx, wy);
      } else {
        emit(w, w, w);
      }
    }
    const __mmask8 tan_ok = _mm512_cmp_pd_mask(_mm512_abs_pd(t), bcast(kMaxTan), _CMP_LE_OQ);
    const __mmask8 r_ok = _mm512_cmp_pd_mask(rn, rtol, _CMP_GE_OQ);
    ok = static_cast<__mmask8>(ok & tan_ok & r_ok);
    sx = sxn, sy = syn, r = rn, irc = _mm512_mul_pd(rn, ir2n), tp = t;
    if constexpr (kGrad) gtpx = gtx, gtpy = gty, nx = nxn, ny = nyn;
    next = after;
  }
};

/// The whole polygon: emit(i, w_i, ∂x w_i, ∂y w_i) for i = 0 .. n−1 (n ≥ 3).
template <bool kGrad, bool kTwoDivisions, class Emit>
inline void walk_polygon(Walk& a, const double* vx, const double* vy, int n, Emit&& emit) {
  a.start(vx[n - 1], vy[n - 1], vx[0], vy[0]);
  a.template edge<kGrad, false, kTwoDivisions>(vx[1], vy[1], [](__m512d, __m512d, __m512d) {});
  for (int i = 0; i < n; ++i) {
    int j = i + 2;
    if (j >= n) j -= n;
    a.template edge<kGrad, true, kTwoDivisions>(
        vx[j], vy[j], [&](__m512d w, __m512d wx, __m512d wy) { emit(i, w, wx, wy); });
  }
}

/// A walk at eight points (lanes past `m` get a finite dummy point; never stored).
inline Walk begin_walk(const double* vx, const double* vy, int n, const double* px, const double* py, int p0,
                       __mmask8 m, double rtol) {
  Walk a;
  a.px = _mm512_mask_loadu_pd(bcast(0.5 * (vx[0] + vx[n / 2])), m, px + p0);
  a.py = _mm512_mask_loadu_pd(bcast(0.5 * (vy[0] + vy[n / 2])), m, py + p0);
  a.rtol = bcast(rtol);
  a.tp = a.gtpx = a.gtpy = _mm512_setzero_pd();
  return a;
}

inline __mmask8 lane_mask(int remaining) {
  return remaining >= 8 ? static_cast<__mmask8>(0xFF) : static_cast<__mmask8>((1u << remaining) - 1u);
}

inline void write_robust(__mmask8 ok, __mmask8 m, int p0, unsigned char* robust) {
  for (int l = 0; l < 8; ++l)
    if ((m >> l) & 1) robust[p0 + l] = ((ok >> l) & 1) ? 0 : 1;
}

template <bool kGrad>
void map_step_impl(const double* vx, const double* vy, const double* ux, const double* uy, int n,
                   const double* px, const double* py, int cnt, double rtol, double* fx, double* fy,
                   double* J, int ldJ, unsigned char* robust) {
  for (int p0 = 0; p0 < cnt; p0 += 8) {
    const __mmask8 m = lane_mask(cnt - p0);
    Walk walk = begin_walk(vx, vy, n, px, py, p0, m, rtol);
    __m512d W = _mm512_setzero_pd(), Fx = W, Fy = W, Wx = W, Wy = W, Gxx = W, Gxy = W, Gyx = W, Gyy = W;
    walk_polygon<kGrad, kGrad>(walk, vx, vy, n, [&](int i, __m512d w, __m512d wx, __m512d wy) {
      const __m512d a = bcast(ux[i]), b = bcast(uy[i]);
      W = _mm512_add_pd(W, w);
      Fx = _mm512_fmadd_pd(w, a, Fx);
      Fy = _mm512_fmadd_pd(w, b, Fy);
      if constexpr (kGrad) {
        Wx = _mm512_add_pd(Wx, wx);
        Wy = _mm512_add_pd(Wy, wy);
        Gxx = _mm512_fmadd_pd(a, wx, Gxx);
        Gxy = _mm512_fmadd_pd(a, wy, Gxy);
        Gyx = _mm512_fmadd_pd(b, wx, Gyx);
        Gyy = _mm512_fmadd_pd(b, wy, Gyy);
      }
    });
    const __m512d iW = _mm512_div_pd(bcast(1.0), W);
    const __m512d dx = _mm512_mul_pd(Fx, iW), dy = _mm512_mul_pd(Fy, iW);
    _mm512_mask_storeu_pd(fx + p0, m, _mm512_add_pd(walk.px, dx));
    _mm512_mask_storeu_pd(fy + p0, m, _mm512_add_pd(walk.py, dy));
    if constexpr (kGrad) {
      const __m512d one = bcast(1.0);
      _mm512_mask_storeu_pd(J + p0, m, _mm512_fmadd_pd(_mm512_fnmadd_pd(dx, Wx, Gxx), iW, one));
      _mm512_mask_storeu_pd(J + ldJ + p0, m, _mm512_mul_pd(_mm512_fnmadd_pd(dx, Wy, Gxy), iW));
      _mm512_mask_storeu_pd(J + 2 * ldJ + p0, m, _mm512_mul_pd(_mm512_fnmadd_pd(dy, Wx, Gyx), iW));
      _mm512_mask_storeu_pd(J + 3 * ldJ + p0, m, _mm512_fmadd_pd(_mm512_fnmadd_pd(dy, Wy, Gyy), iW, one));
    }
    write_robust(walk.ok, m, p0, robust);
  }
}

/// Unnormalized weights stay in a buffer until W is known, for G groups of
/// eight points at a time (G n ≤ kBuffered, G ≤ kMaxGroups). The normalized
/// outputs are then written row by row, the G groups' lines of one output row
/// back to back. Writing one group's 3n lines at once, one per output row, is
/// slow when the stride ld is a multiple of 2 KiB (batches of 256 or 512
/// points): all of them then fall into one or two L1 sets. Zen 4, 256-point
/// batches of a 32-gon, values + gradients: 12.6–13.2 M points/s one group at
/// a time, 13.8–14.2 M with G = 4, 14.1–15.3 M with G = 8, 16.4–16.6 M with
/// G = 8 and vertex-major records (the row pass then reads the buffer in
/// order; G = 4 or 16 were slower); values 22–24 → 25–27 M.
constexpr int kBuffered = 256;
constexpr int kMaxGroups = 8;

template <bool kGrad>
void coordinates_unbuffered(const double* vx, const double* vy, int n, const double* px, const double* py,
                            int cnt, double rtol, double* phi, double* dxo, double* dyo, long ld,
                            unsigned char* robust) {
  for (int p0 = 0; p0 < cnt; p0 += 8) {
    const __mmask8 m = lane_mask(cnt - p0);
    Walk walk = begin_walk(vx, vy, n, px, py, p0, m, rtol);
    __m512d W = _mm512_setzero_pd(), Wx = W, Wy = W;
    walk_polygon<kGrad, false>(walk, vx, vy, n, [&](int i, __m512d w, __m512d wx, __m512d wy) {
      W = _mm512_add_pd(W, w);
      _mm512_mask_storeu_pd(phi + i * ld + p0, m, w);
      if constexpr (kGrad) {
        Wx = _mm512_add_pd(Wx, wx);
        Wy = _mm512_add_pd(Wy, wy);
        _mm512_mask_storeu_pd(dxo + i * ld + p0, m, wx);
        _mm512_mask_storeu_pd(dyo + i * ld + p0, m, wy);
      }
    });
    // Normalize in place: φ = w/W, ∇φ = (∇w − φ ∇W)/W.
    const __m512d iW = _mm512_div_pd(bcast(1.0), W);
    for (int i = 0; i < n; ++i) {
      double* f = phi + i * ld + p0;
      const __m512d ph = _mm512_mul_pd(_mm512_maskz_loadu_pd(m, f), iW);
      _mm512_mask_storeu_pd(f, m, ph);
      if constexpr (kGrad) {
        double* gx = dxo + i * ld + p0;
        double* gy = dyo + i * ld + p0;
        _mm512_mask_storeu_pd(gx, m,
                              _mm512_mul_pd(_mm512_fnmadd_pd(ph, Wx, _mm512_maskz_loadu_pd(m, gx)), iW));
        _mm512_mask_storeu_pd(gy, m,
                              _mm512_mul_pd(_mm512_fnmadd_pd(ph, Wy, _mm512_maskz_loadu_pd(m, gy)), iW));
      }
    }
    write_robust(walk.ok, m, p0, robust);
  }
}

template <bool kGrad>
void coordinates_impl(const double* vx, const double* vy, int n, const double* px, const double* py, int cnt,
                      double rtol, double* phi, double* dxo, double* dyo, long ld, unsigned char* robust) {
  if (n > kBuffered) {
    coordinates_unbuffered<kGrad>(vx, vy, n, px, py, cnt, rtol, phi, dxo, dyo, ld, robust);
    return;
  }
  // One record per (vertex i, group g): w, and with gradients ∂x w, ∂y w (one
  // cache line each). Values keep a group's vertices together (g major), the
  // gradient records are vertex major, so the row-by-row pass reads them in
  // order (A/B: values + gradients +5-9 %, values −3 % with that layout).
  // Two banks (~97 KB of stack with gradients): the normalization of one tile
  // is spread over the walk of the next, one (row, group) pair per vertex
  // step, so its loads, FMAs and stores fill the slack of the walk, which
  // waits on the divider (Zen 4, 256-point calls: values + gradients
  // 16.7 → 17.9 M points/s, values 26.3 → 28.1 M, alternating runs).
  constexpr int kRecord = kGrad ? 3 : 1;
  struct Tile {
    int q0 = 0, groups = 0, done = 0;
    __m512d iW[kMaxGroups], Wx[kMaxGroups], Wy[kMaxGroups];
    __mmask8 mask[kMaxGroups];
    alignas(64) double buffer[kBuffered][kRecord][8];
  };
  Tile bank[2];
  const int G = kBuffered / n < kMaxGroups ? kBuffered / n : kMaxGroups;
  const auto slot = [G, n](int i, int g) { return kGrad ? i * G + g : g * n + i; };
  // Normalizes the k-th (row, group) pair of a finished tile: φ = w/W,
  // ∇φ = (∇w − φ ∇W)/W.
  const auto normalize = [&](const Tile& t, int k) {
    const int i = k / t.groups, g = k - i * t.groups;
    const double(*record)[8] = t.buffer[slot(i, g)];
    const long at = i * ld + t.q0 + 8 * g;
    const __m512d ph = _mm512_mul_pd(_mm512_load_pd(record[0]), t.iW[g]);
    _mm512_mask_storeu_pd(phi + at, t.mask[g], ph);
    if constexpr (kGrad) {
      const __m512d wx = _mm512_load_pd(record[1]);
      const __m512d wy = _mm512_load_pd(record[2]);
      _mm512_mask_storeu_pd(dxo + at, t.mask[g], _mm512_mul_pd(_mm512_fnmadd_pd(ph, t.Wx[g], wx), t.iW[g]));
      _mm512_mask_storeu_pd(dyo + at, t.mask[g], _mm512_mul_pd(_mm512_fnmadd_pd(ph, t.Wy[g], wy), t.iW[g]));
    }
  };
  Tile* pending = nullptr;  // finished, not yet (fully) normalized
  int which = 0;
  for (int q0 = 0; q0 < cnt; q0 += 8 * G, which ^= 1) {
    Tile& t = bank[which];
    t.q0 = q0;
    t.groups = 0;
    t.done = 0;
    for (; t.groups < G && q0 + 8 * t.groups < cnt; ++t.groups) {
      const int g = t.groups;
      const int p0 = q0 + 8 * g;
      const __mmask8 m = lane_mask(cnt - p0);
      Walk walk = begin_walk(vx, vy, n, px, py, p0, m, rtol);
      __m512d W = _mm512_setzero_pd(), Sx = W, Sy = W;
      walk_polygon<kGrad, false>(walk, vx, vy, n, [&](int i, __m512d w, __m512d wx, __m512d wy) {
        double(*record)[8] = t.buffer[slot(i, g)];
        W = _mm512_add_pd(W, w);
        _mm512_store_pd(record[0], w);
        if constexpr (kGrad) {
          Sx = _mm512_add_pd(Sx, wx);
          Sy = _mm512_add_pd(Sy, wy);
          _mm512_store_pd(record[1], wx);
          _mm512_store_pd(record[2], wy);
        }
        if (pending && pending->done < n * pending->groups) normalize(*pending, pending->done++);
      });
      t.iW[g] = _mm512_div_pd(bcast(1.0), W);
      t.Wx[g] = Sx;
      t.Wy[g] = Sy;
      t.mask[g] = m;
      write_robust(walk.ok, m, p0, robust);
    }
    if (pending)
      while (pending->done < n * pending->groups) normalize(*pending, pending->done++);
    pending = &t;
  }
  if (pending)
    while (pending->done < n * pending->groups) normalize(*pending, pending->done++);
}

}  // namespace

void map_step(const double* vx, const double* vy, const double* ux, const double* uy, int n, const double* px,
              const double* py, int cnt, double rtol, double* fx, double* fy, double* J, int ldJ,
              unsigned char* robust) {
  if (J)
    map_step_impl<true>(vx, vy, ux, uy, n, px, py, cnt, rtol, fx, fy, J, ldJ, robust);
  else
    map_step_impl<false>(vx, vy, ux, uy, n, px, py, cnt, rtol, fx, fy, J, ldJ, robust);
}

void coordinates(const double* vx, const double* vy, int n, const double* px, const double* py, int cnt,
                 double rtol, double* phi, double* dx, double* dy, long ld, unsigned char* robust) {
  if (dx)
    coordinates_impl<true>(vx, vy, n, px, py, cnt, rtol, phi, dx, dy, ld, robust);
  else
    coordinates_impl<false>(vx, vy, n, px, py, cnt, rtol, phi, dx, dy, ld, robust);
}

}  // namespace warpfem::mapping::detail::avx512
