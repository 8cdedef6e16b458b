#pragma once
// Internal: the vectorized kernel of polyhedron_mean_value_coordinates.cpp.
//
// For a block of up to kPolyhedronBlock points (normalized coordinates) it first
// forms, per vertex and point, s = p − x, r = |s| and 1/r², then walks over the
// triangles. Per triangle (edges e = 1, 2, 3 opposite vertices 1, 2, 3, i.e.
// N_1 = s_2 × s_3, ...) and point:
//   L_e = |N_e|,  β_e = angle(s_a, s_b) through atan of the half angle,
//   k_e = β_e / (2 L_e),  m = Σ k_e N_e,  D = s_1 · N_1,
//   w_i = m · N_i / D,
// and, with d_e = p_a − p_b (so ∇(N_e · v) = d_e × v), K = Σ k_e d_e,
// M = Σ N_e = (p_2 − p_1) × (p_3 − p_1) (∇D = −M) and q = s / r²,
//   ∇k_e = N_e × (q_a − q_b + 2 k_e d_e) / (2 L_e²),
//   ∇w_i = (Σ_e (N_e · N_i) ∇k_e + K × N_i + d_i × m + w_i M) / D.
// The loops over points are branch-free (selects), so the compiler vectorizes
// them; atan is Cephes' rational approximation (relative error ~1e-17 on
// [0, 0.66]) behind a half-angle reduction, since libm's atan does not vectorize;
// its division shares one reciprocal with 1/L_e.
//
// Points where this loses accuracy are flagged for the robust path: within
// kNearVertex of a vertex, |h| < kNearPlane · min_a r_a for a triangle's plane
// (h = D / |M|), or sin β_e < kNearLine for an edge's line.

#include <cmath>
#include <vector>

#include "mapping/detail/mean_value_kernel.hpp"

namespace warpfem::mapping::detail {

inline constexpr int kPolyhedronBlock = 32;
inline constexpr double kNearPlane = 3e-4;
inline constexpr double kNearLine = 1e-4;
inline constexpr double kPolyhedronNearVertex = 1e-5;

/// atan(n / d) for |n / d| <= 0.66 as n R / d: y + y z P(z) / Q(z) with y = n / d,
/// z = y² (Cephes' minimax coefficients), written homogeneously in u = n², v = d²
/// (z P / Q = u P̃ / Q̃ with P̃ = v⁴ P(u/v), Q̃ = v⁵ Q(u/v)), so that the caller
/// can fold the one division, by d Q̃, into its own. Returns R·Q̃ = Q̃ + u P̃ and Q̃.
/// Coordinates are normalized (|n|, |d| of order 1), so the powers stay in range.
WARPFEM_KERNEL_INLINE void atan_fraction(double n, double d, double& numer, double& denom) {
  const double u = n * n, v = d * d, v2 = v * v, v3 = v2 * v, v4 = v2 * v2, v5 = v4 * v;
  const double P = (((-8.750608600031904122785e-1 * u - 1.615753718733365076637e1 * v) * u -
                     7.500855792314704667340e1 * v2) *
                        u -
                    1.228866684490136173410e2 * v3) *
                       u -
                   6.485021904942025371773e1 * v4;
  const double Q = ((((u + 2.485846490142306297962e1 * v) * u + 1.650270098316988542046e2 * v2) * u +
                     4.328810604912902668951e2 * v3) *
                        u +
                    4.853903996359136964868e2 * v4) *
                       u +
                   1.945506571482613964425e2 * v5;
  numer = Q + u * P;
  denom = Q;
}

/// Per-thread scratch: per vertex and point s, r, 1/r² and the accumulated
/// weights and gradients (vertex-major rows of kPolyhedronBlock).
struct PolyhedronScratch {
  std::vector<double> sx, sy, sz, r, ir2, w, wx, wy, wz;
  alignas(64) double px[kPolyhedronBlock], py[kPolyhedronBlock], pz[kPolyhedronBlock];
  alignas(64) double flag[kPolyhedronBlock];
  void resize(int n) {
    const std::size_t m = static_cast<std::size_t>(n) * kPolyhedronBlock;
    for (auto* v : {&sx, &sy, &sz, &r, &ir2, &w, &wx, &wy, &wz}) v->assign(m, 0.0);
  }
};

/// Accumulates the weights (and gradients) of `cnt` points (normalized, in
/// s.px/py/pz) into s.w (s.wx, wy, wz), and sets s.flag[p] for points that need
/// the robust path.
template <bool kGrad>
WARPFEM_KERNEL_INLINE void polyhedron_block(const double* vx, const double* vy, const double* vz, int n,
                                            const int* ta, const int* tb, const int* tc, int m, int cnt,
                                            PolyhedronScratch& s) {
  constexpr int B = kPolyhedronBlock;
  for (int p = 0; p < cnt; ++p) s.flag[p] = 0.0;
  for (int v = 0; v < n; ++v) {
    double* __restrict sx = s.sx.data() + v * B;
    double* __restrict sy = s.sy.data() + v * B;
    double* __restrict sz = s.sz.data() + v * B;
    double* __restrict r = s.r.data() + v * B;
    double* __restrict ir2 = s.ir2.data() + v * B;
    double* __restrict w = s.w.data() + v * B;
    const double ax = vx[v], ay = vy[v], az = vz[v];
    WARPFEM_IVDEP
    for (int p = 0; p < cnt; ++p) {
      const double x = ax - s.px[p], y = ay - s.py[p], z = az - s.pz[p];
      const double r2 = x * x + y * y + z * z;
      sx[p] = x;
      sy[p] = y;
      sz[p] = z;
      r[p] = std::sqrt(r2);
      ir2[p] = 1.0 / r2;
      w[p] = 0.0;
      s.flag[p] = r[p] < kPolyhedronNearVertex ? 1.0 : s.flag[p];
    }
    if constexpr (kGrad) {
      for (int p = 0; p < cnt; ++p) s.wx[v * B + p] = s.wy[v * B + p] = s.wz[v * B + p] = 0.0;
    }
  }
  for (int t = 0; t < m; ++t) {
    const int i1 = ta[t], i2 = tb[t], i3 = tc[t];
    // Triangle constants: d_e = p_a − p_b for e = (a, b) = (2, 3), (3, 1), (1, 2); M = Σ N_e.
    const double d1x = vx[i2] - vx[i3], d1y = vy[i2] - vy[i3], d1z = vz[i2] - vz[i3];
    const double d2x = vx[i3] - vx[i1], d2y = vy[i3] - vy[i1], d2z = vz[i3] - vz[i1];
    const double d3x = vx[i1] - vx[i2], d3y = vy[i1] - vy[i2], d3z = vz[i1] - vz[i2];
    const double Mx = d2y * d3z - d2z * d3y, My = d2z * d3x - d2x * d3z, Mz = d2x * d3y - d2y * d3x;
    const double absM = std::sqrt(Mx * Mx + My * My + Mz * Mz);
    const double* __restrict s1x = s.sx.data() + i1 * B;
    const double* __restrict s1y = s.sy.data() + i1 * B;
    const double* __restrict s1z = s.sz.data() + i1 * B;
    const double* __restrict s2x = s.sx.data() + i2 * B;
    const double* __restrict s2y = s.sy.data() + i2 * B;
    const double* __restrict s2z = s.sz.data() + i2 * B;
    const double* __restrict s3x = s.sx.data() + i3 * B;
    const double* __restrict s3y = s.sy.data() + i3 * B;
    const double* __restrict s3z = s.sz.data() + i3 * B;
    const double* __restrict r1 = s.r.data() + i1 * B;
    const double* __restrict r2 = s.r.data() + i2 * B;
    const double* __restrict r3 = s.r.data() + i3 * B;
    const double* __restrict q1 = s.ir2.data() + i1 * B;
    const double* __restrict q2 = s.ir2.data() + i2 * B;
    const double* __restrict q3 = s.ir2.data() + i3 * B;
    double* __restrict w1 = s.w.data() + i1 * B;
    double* __restrict w2 = s.w.data() + i2 * B;
    double* __restrict w3 = s.w.data() + i3 * B;
    double* __restrict g1x = s.wx.data() + i1 * B;
    double* __restrict g1y = s.wy.data() + i1 * B;
    double* __restrict g1z = s.wz.data() + i1 * B;
    double* __restrict g2x = s.wx.data() + i2 * B;
    double* __restrict g2y = s.wy.data() + i2 * B;
    double* __restrict g2z = s.wz.data() + i2 * B;
    double* __restrict g3x = s.wx.data() + i3 * B;
    double* __restrict g3y = s.wy.data() + i3 * B;
    double* __restrict g3z = s.wz.data() + i3 * B;
    WARPFEM_IVDEP
    for (int p = 0; p < cnt; ++p) {
      const double ax = s1x[p], ay = s1y[p], az = s1z[p];
      const double bx = s2x[p], by = s2y[p], bz = s2z[p];
      const double cx = s3x[p], cy = s3y[p], cz = s3z[p];
      // N_1 = s_2 × s_3, N_2 = s_3 × s_1, N_3 = s_1 × s_2.
      const double n1x = by * cz - bz * cy, n1y = bz * cx - bx * cz, n1z = bx * cy - by * cx;
      const double n2x = cy * az - cz * ay, n2y = cz * ax - cx * az, n2z = cx * ay - cy * ax;
      const double n3x = ay * bz - az * by, n3y = az * bx - ax * bz, n3z = ax * by - ay * bx;
      const double L1 = std::sqrt(n1x * n1x + n1y * n1y + n1z * n1z);
      const double L2 = std::sqrt(n2x * n2x + n2y * n2y + n2z * n2z);
      const double L3 = std::sqrt(n3x * n3x + n3y * n3y + n3z * n3z);
      const double c1 = bx * cx + by * cy + bz * cz, c2 = cx * ax + cy * ay + cz * az,
                   c3 = ax * bx + ay * by + az * bz;
      const double rr1 = r2[p] * r3[p], rr2 = r3[p] * r1[p], rr3 = r1[p] * r2[p];
      // k_e = β_e / (2 L_e) with tan(β/2) = L / (rr + c) = (rr − c) / L: take the
      // form whose value is <= 1, atan(L / den) with den = rr + |c|; above 0.66
      // reduce by π/4: atan(z) = π/4 + atan((z − 1) / (z + 1)). One division
      // gives both that argument and 1/L.
      const auto half_angle = [](double L, double c, double rr, double& iL) {
        const double den = rr + std::abs(c);
        const bool big = L > 0.66 * den;
        const double num_y = big ? L - den : L;
        const double den_y = big ? L + den : den;
        double R, Q;
        atan_fraction(num_y, den_y, R, Q);
        const double f = 1.0 / (L * den_y * Q);  // the one division: 1/L and atan(num_y/den_y)
        iL = den_y * Q * f;
        const double a = (big ? 0.78539816339744830962 : 0.0) + num_y * R * L * f;
        return (c >= 0.0 ? a : 1.57079632679489661923 - a) * iL;
      };
      double iL1, iL2, iL3;
      const double k1 = half_angle(L1, c1, rr1, iL1);
      const double k2 = half_angle(L2, c2, rr2, iL2);
      const double k3 = half_angle(L3, c3, rr3, iL3);
      const double D = ax * n1x + ay * n1y + az * n1z;
      const double r12 = r1[p] < r2[p] ? r1[p] : r2[p];
      const double rmin = r12 < r3[p] ? r12 : r3[p];
      // Flags summed as numbers: boolean logic here makes GCC branch and not vectorize.
      s.flag[p] += (std::abs(D) < kNearPlane * rmin * absM ? 1.0 : 0.0) + (L1 < kNearLine * rr1 ? 1.0 : 0.0) +
                   (L2 < kNearLine * rr2 ? 1.0 : 0.0) + (L3 < kNearLine * rr3 ? 1.0 : 0.0);
      const double iD = 1.0 / D;
      const double mx = k1 * n1x + k2 * n2x + k3 * n3x;
      const double my = k1 * n1y + k2 * n2y + k3 * n3y;
      const double mz = k1 * n1z + k2 * n2z + k3 * n3z;
      const double e1 = (mx * n1x + my * n1y + mz * n1z) * iD;
      const double e2 = (mx * n2x + my * n2y + mz * n2z) * iD;
      const double e3 = (mx * n3x + my * n3y + mz * n3z) * iD;
      w1[p] += e1;
      w2[p] += e2;
      w3[p] += e3;
      if constexpr (kGrad) {
        // Gram matrix of the N_e.
        const double G11 = L1 * L1, G22 = L2 * L2, G33 = L3 * L3;
        const double G12 = n1x * n2x + n1y * n2y + n1z * n2z;
        const double G13 = n1x * n3x + n1y * n3y + n1z * n3z;
        const double G23 = n2x * n3x + n2y * n3y + n2z * n3z;
        // ∇k_e = N_e × u_e / (2 L_e²), u_e = q_a − q_b + 2 k_e d_e, q = s / r².
        const double qax = ax * q1[p], qay = ay * q1[p], qaz = az * q1[p];
        const double qbx = bx * q2[p], qby = by * q2[p], qbz = bz * q2[p];
        const double qcx = cx * q3[p], qcy = cy * q3[p], qcz = cz * q3[p];
        const double h1 = 0.5 * iL1 * iL1, h2 = 0.5 * iL2 * iL2, h3 = 0.5 * iL3 * iL3;
        const double u1x = qbx - qcx + 2 * k1 * d1x, u1y = qby - qcy + 2 * k1 * d1y,
                     u1z = qbz - qcz + 2 * k1 * d1z;
        const double u2x = qcx - qax + 2 * k2 * d2x, u2y = qcy - qay + 2 * k2 * d2y,
                     u2z = qcz - qaz + 2 * k2 * d2z;
        const double u3x = qax - qbx + 2 * k3 * d3x, u3y = qay - qby + 2 * k3 * d3y,
                     u3z = qaz - qbz + 2 * k3 * d3z;
        const double k1x = (n1y * u1z - n1z * u1y) * h1, k1y = (n1z * u1x - n1x * u1z) * h1,
                     k1z = (n1x * u1y - n1y * u1x) * h1;
        const double k2x = (n2y * u2z - n2z * u2y) * h2, k2y = (n2z * u2x - n2x * u2z) * h2,
                     k2z = (n2x * u2y - n2y * u2x) * h2;
        const double k3x = (n3y * u3z - n3z * u3y) * h3, k3y = (n3z * u3x - n3x * u3z) * h3,
                     k3z = (n3x * u3y - n3y * u3x) * h3;
        const double Kx = k1 * d1x + k2 * d2x + k3 * d3x;
        const double Ky = k1 * d1y + k2 * d2y + k3 * d3y;
        const double Kz = k1 * d1z + k2 * d2z + k3 * d3z;
        // ∇w_i = (Σ_e G_ei ∇k_e + K × N_i + d_i × m + w_i M) / D.
        const auto grad = [&](double Ga, double Gb, double Gc, double nx, double ny, double nz, double dx,
                              double dy, double dz, double wi, double* gx, double* gy, double* gz) {
          gx[p] += (Ga * k1x + Gb * k2x + Gc * k3x + Ky * nz - Kz * ny + dy * mz - dz * my + wi * Mx) * iD;
          gy[p] += (Ga * k1y + Gb * k2y + Gc * k3y + Kz * nx - Kx * nz + dz * mx - dx * mz + wi * My) * iD;
          gz[p] += (Ga * k1z + Gb * k2z + Gc * k3z + Kx * ny - Ky * nx + dx * my - dy * mx + wi * Mz) * iD;
        };
        grad(G11, G12, G13, n1x, n1y, n1z, d1x, d1y, d1z, e1, g1x, g1y, g1z);
        grad(G12, G22, G23, n2x, n2y, n2z, d2x, d2y, d2z, e2, g2x, g2y, g2z);
        grad(G13, G23, G33, n3x, n3y, n3z, d3x, d3y, d3z, e3, g3x, g3y, g3z);
      }
    }
  }
}

}  // namespace warpfem::mapping::detail
