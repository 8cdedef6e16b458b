#pragma once
// Internal: the vectorized kernel of polyhedron_mean_value_coordinates.cpp.
//
// For a block of up to kPolyhedronBlock points (normalized coordinates) it
// forms, per vertex and point, s = p − x and r = |s|; per edge (a, b)
// and point, once for the two triangles that share it,
//   L_e = |s_a × s_b|,  c_e = s_a · s_b,  β_e = angle(s_a, s_b) through atan of
//   the half angle,  k_e = β_e / (2 L_e),  1/L_e;
// then per triangle (edges e = 1, 2, 3 opposite vertices 1, 2, 3, i.e.
// N_1 = s_2 × s_3, ...) and point:
//   m = Σ k_e N_e,  D = s_1 · N_1,  w_i = m · N_i / D.
// Since w = S⁻¹ m with S = (s_1 s_2 s_3), the gradient is
//   ∂_j w_i = N_i · (∂_j m + W e_j) / D,  W = Σ_i w_i,
//   ∂_j m = Σ_e ∂_j k_e N_e + e_j × K,  K = Σ_e k_e (s_a − s_b),
//   ∇k_e = N_e × (s_a / r_a² − s_b / r_b² + 2 k_e (s_a − s_b)) / (2 L_e²).
// The loops over points are branch-free (selects), so the compiler vectorizes
// them; atan is Cephes' rational approximation (relative error ~1e-17 on
// [0, 0.66]) behind a half-angle reduction, since libm's atan does not vectorize;
// its division shares one reciprocal with 1/L_e and, for the gradient,
// 1/(r_a r_b)² (so the vertices need no division). The edges are computed
// just ahead of the triangles that use them (PolyhedronArrays::order), into a
// few reused slots, and the scratch is stored in contiguous records per vertex
// and per slot: a block's scratch is small (122 KB for 32 points on a 50-vertex
// cage, in L2) and neighbouring triangles find their data together. 32 points
// (four AVX-512 vectors per loop) give more independent work per edge's chain
// of square root, atan and division than 16; the outputs' rows then span more
// pages, which 2 MiB pages (core/huge_pages.hpp) keep cheap.
//
// Points where this loses accuracy are flagged for the robust path: within
// kNearVertex of a vertex, or sin β_e < kNearLine for an edge's line. A
// triangle whose plane passes within kNearPlane · min_a r_a of x (h = D / |M|)
// is left out and recorded; the caller adds its contribution in the h-factored
// form (or takes the robust path when x is near several such planes or near
// the surface).

#include <algorithm>
#include <cmath>
#include <vector>

#include "mapping/detail/mean_value_kernel.hpp"
#include "mapping/polyhedron_mean_value_coordinates.hpp"

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

/// Per-thread scratch, in records of kPolyhedronBlock points: per vertex
/// (s_x, s_y, s_z, r) and the accumulated (w, ∂_x w, ∂_y w, ∂_z w), per
/// edge slot (k, ∂_x k, ∂_y k, ∂_z k). Each record is contiguous, and the slots
/// are reused (PolyhedronArrays::edge_slot), so a block's scratch stays small.
struct PolyhedronScratch {
  static constexpr int kVertexRows = 4, kWeightRows = 4, kSlotRows = 4;
  std::vector<double> vertex, weight, slot;
  alignas(64) double px[kPolyhedronBlock], py[kPolyhedronBlock], pz[kPolyhedronBlock];
  alignas(64) double flag[kPolyhedronBlock];
  /// Faces whose plane passes near the point, left out: how many, and the sum of their indices.
  alignas(64) double plane[kPolyhedronBlock], plane_face[kPolyhedronBlock];
  void resize(const PolyhedronArrays& P) {
    const std::size_t n = static_cast<std::size_t>(P.size()) * kPolyhedronBlock;
    vertex.assign(kVertexRows * n, 0.0);
    weight.assign(kWeightRows * n, 0.0);
    slot.assign(
        static_cast<std::size_t>(kSlotRows) * static_cast<std::size_t>(P.slot_count) * kPolyhedronBlock, 0.0);
  }
  double* vertex_row(int v, int row) { return vertex.data() + (kVertexRows * v + row) * kPolyhedronBlock; }
  double* weight_row(int v, int row) { return weight.data() + (kWeightRows * v + row) * kPolyhedronBlock; }
  double* slot_row(int e, int row) { return slot.data() + (kSlotRows * e + row) * kPolyhedronBlock; }
};

/// k = β / (2 L) and 1/L for an edge with L = |s_a × s_b|, c = s_a · s_b and
/// rr = r_a r_b. tan(β/2) = L / (rr + c) = (rr − c) / L: the form whose value
/// is <= 1 is atan(L / den) with den = rr + |c|; above 0.66 it is reduced by
/// π/4, atan(z) = π/4 + atan((z − 1) / (z + 1)). One division gives both that
/// argument and 1/L, and with kGrad also irr2 = 1/rr².
template <bool kGrad>
WARPFEM_KERNEL_INLINE double half_angle(double L, double c, double rr, double& iL, double& irr2) {
  const double den = rr + std::abs(c);
  // 1 or 0 as a number: a boolean used three times makes GCC branch and not vectorize.
  const double big = L > 0.66 * den ? 1.0 : 0.0;
  const double num_y = L - big * den;
  const double den_y = den + big * L;
  double R, Q;
  atan_fraction(num_y, den_y, R, Q);
  double a;
  if constexpr (kGrad) {
    // The same division also gives 1/rr², from which ∇k takes 1/r_a² and 1/r_b².
    const double rr2 = rr * rr;
    const double f = 1.0 / (L * den_y * rr2 * Q);
    iL = den_y * rr2 * Q * f;
    irr2 = L * den_y * Q * f;
    a = big * 0.78539816339744830962 + num_y * R * (L * rr2) * f;
  } else {
    const double f = 1.0 / (L * den_y * Q);
    iL = den_y * Q * f;
    irr2 = 0;
    a = big * 0.78539816339744830962 + num_y * R * L * f;
  }
  return (c >= 0.0 ? a : 1.57079632679489661923 - a) * iL;
}

/// k and ∇k of edge (a, b) for the points of the block, into its slot.
template <bool kGrad>
WARPFEM_KERNEL_INLINE void polyhedron_edge(PolyhedronScratch& s, int a, int b, int slot) {
  constexpr int B = kPolyhedronBlock;
  const double* __restrict sax = s.vertex_row(a, 0);
  const double* __restrict say = s.vertex_row(a, 1);
  const double* __restrict saz = s.vertex_row(a, 2);
  const double* __restrict ra = s.vertex_row(a, 3);
  const double* __restrict sbx = s.vertex_row(b, 0);
  const double* __restrict sby = s.vertex_row(b, 1);
  const double* __restrict sbz = s.vertex_row(b, 2);
  const double* __restrict rb = s.vertex_row(b, 3);
  double* __restrict ek = s.slot_row(slot, 0);
  double* __restrict ekx = s.slot_row(slot, 1);
  double* __restrict eky = s.slot_row(slot, 2);
  double* __restrict ekz = s.slot_row(slot, 3);
  double* __restrict flag = s.flag;
  WARPFEM_IVDEP
  for (int p = 0; p < B; ++p) {
    const double ax = sax[p], ay = say[p], az = saz[p];
    const double bx = sbx[p], by = sby[p], bz = sbz[p];
    const double nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    const double L = std::sqrt(nx * nx + ny * ny + nz * nz);
    const double c = ax * bx + ay * by + az * bz;
    const double rr = ra[p] * rb[p];
    double iL, irr2;
    const double k = half_angle<kGrad>(L, c, rr, iL, irr2);
    ek[p] = k;
    if constexpr (kGrad) {
      // ∇k = N × (q_a − q_b + 2 k (s_a − s_b)) / (2 L²), q = s / r², expanded with
      // (s_a × s_b) × v = (s_a · v) s_b − (s_b · v) s_a into α s_a + γ s_b:
      //   α = 1 − c / r_a² + 2 k (r_b² − c),  γ = 1 − c / r_b² + 2 k (r_a² − c),
      // with 1 / r_a² = r_b² / rr².
      const double h = 0.5 * iL * iL, k2 = k + k, ra2 = ra[p] * ra[p], rb2 = rb[p] * rb[p];
      const double al = (1.0 - c * rb2 * irr2 + k2 * (rb2 - c)) * h;
      const double ga = (1.0 - c * ra2 * irr2 + k2 * (ra2 - c)) * h;
      ekx[p] = al * ax + ga * bx;
      eky[p] = al * ay + ga * by;
      ekz[p] = al * az + ga * bz;
    }
    // Flags summed as numbers: boolean logic here makes GCC branch and not vectorize.
    flag[p] += L < kNearLine * rr ? 1.0 : 0.0;
  }
}

/// Triangle t's contribution to the weights (and gradients) of its vertices.
template <bool kGrad>
WARPFEM_KERNEL_INLINE void polyhedron_triangle(const PolyhedronArrays& P, PolyhedronScratch& s, int t) {
  constexpr int B = kPolyhedronBlock;
  const int i1 = P.a[t], i2 = P.b[t], i3 = P.c[t];
  const int e1 = P.edge_slot[P.triangle_edges[3 * t]], e2 = P.edge_slot[P.triangle_edges[3 * t + 1]],
            e3 = P.edge_slot[P.triangle_edges[3 * t + 2]];
  const double near_plane = kNearPlane * P.two_area[t], face = static_cast<double>(t);
  const double* __restrict s1x = s.vertex_row(i1, 0);
  const double* __restrict s1y = s.vertex_row(i1, 1);
  const double* __restrict s1z = s.vertex_row(i1, 2);
  const double* __restrict r1 = s.vertex_row(i1, 3);
  const double* __restrict s2x = s.vertex_row(i2, 0);
  const double* __restrict s2y = s.vertex_row(i2, 1);
  const double* __restrict s2z = s.vertex_row(i2, 2);
  const double* __restrict r2 = s.vertex_row(i2, 3);
  const double* __restrict s3x = s.vertex_row(i3, 0);
  const double* __restrict s3y = s.vertex_row(i3, 1);
  const double* __restrict s3z = s.vertex_row(i3, 2);
  const double* __restrict r3 = s.vertex_row(i3, 3);
  const double* __restrict ek1 = s.slot_row(e1, 0);
  const double* __restrict ek2 = s.slot_row(e2, 0);
  const double* __restrict ek3 = s.slot_row(e3, 0);
  const double* __restrict gk1x = s.slot_row(e1, 1);
  const double* __restrict gk1y = s.slot_row(e1, 2);
  const double* __restrict gk1z = s.slot_row(e1, 3);
  const double* __restrict gk2x = s.slot_row(e2, 1);
  const double* __restrict gk2y = s.slot_row(e2, 2);
  const double* __restrict gk2z = s.slot_row(e2, 3);
  const double* __restrict gk3x = s.slot_row(e3, 1);
  const double* __restrict gk3y = s.slot_row(e3, 2);
  const double* __restrict gk3z = s.slot_row(e3, 3);
  double* __restrict w1 = s.weight_row(i1, 0);
  double* __restrict w2 = s.weight_row(i2, 0);
  double* __restrict w3 = s.weight_row(i3, 0);
  double* __restrict g1x = s.weight_row(i1, 1);
  double* __restrict g1y = s.weight_row(i1, 2);
  double* __restrict g1z = s.weight_row(i1, 3);
  double* __restrict g2x = s.weight_row(i2, 1);
  double* __restrict g2y = s.weight_row(i2, 2);
  double* __restrict g2z = s.weight_row(i2, 3);
  double* __restrict g3x = s.weight_row(i3, 1);
  double* __restrict g3y = s.weight_row(i3, 2);
  double* __restrict g3z = s.weight_row(i3, 3);
  double* __restrict plane = s.plane;
  double* __restrict plane_face = s.plane_face;
  WARPFEM_IVDEP
  for (int p = 0; p < B; ++p) {
    const double ax = s1x[p], ay = s1y[p], az = s1z[p];
    const double bx = s2x[p], by = s2y[p], bz = s2z[p];
    const double cx = s3x[p], cy = s3y[p], cz = s3z[p];
    // N_1 = s_2 × s_3, N_2 = s_3 × s_1, N_3 = s_1 × s_2.
    const double n1x = by * cz - bz * cy, n1y = bz * cx - bx * cz, n1z = bx * cy - by * cx;
    const double n2x = cy * az - cz * ay, n2y = cz * ax - cx * az, n2z = cx * ay - cy * ax;
    const double n3x = ay * bz - az * by, n3y = az * bx - ax * bz, n3z = ax * by - ay * bx;
    const double k1 = ek1[p], k2 = ek2[p], k3 = ek3[p];
    const double D = ax * n1x + ay * n1y + az * n1z;
    const double r12 = r1[p] < r2[p] ? r1[p] : r2[p];
    const double rmin = r12 < r3[p] ? r12 : r3[p];
    // A face whose plane passes near x (and x projects outside it, or x is near the
    // surface) loses accuracy here: it is left out (iD = 0) and recorded.
    // (Numbers, not booleans: those make GCC branch and not vectorize.)
    const double near = std::abs(D) < near_plane * rmin ? 1.0 : 0.0;
    plane[p] += near;
    plane_face[p] += near * face;  // the face, when it is the only one
    const double iD = (1.0 - near) / (D + near);
    const double mx = k1 * n1x + k2 * n2x + k3 * n3x;
    const double my = k1 * n1y + k2 * n2y + k3 * n3y;
    const double mz = k1 * n1z + k2 * n2z + k3 * n3z;
    const double o1 = (mx * n1x + my * n1y + mz * n1z) * iD;
    const double o2 = (mx * n2x + my * n2y + mz * n2z) * iD;
    const double o3 = (mx * n3x + my * n3y + mz * n3z) * iD;
    w1[p] += o1;
    w2[p] += o2;
    w3[p] += o3;
    if constexpr (kGrad) {
      // w = S⁻¹ m with S = (s_1 s_2 s_3) (rows of S⁻¹: N_i / D), and ∂S/∂x_j = −e_j 1ᵀ, so
      // ∂_j w_i = N_i · C_j / D with C_j = ∂_j m + W e_j, W = Σ_i w_i, and
      // ∂_j m = Σ_e ∇k_e[j] N_e + e_j × K, K = Σ_e k_e (s_a − s_b).
      const double k1x = gk1x[p], k1y = gk1y[p], k1z = gk1z[p];
      const double k2x = gk2x[p], k2y = gk2y[p], k2z = gk2z[p];
      const double k3x = gk3x[p], k3y = gk3y[p], k3z = gk3z[p];
      // K = (k_3 − k_2) s_1 + (k_1 − k_3) s_2 + (k_2 − k_1) s_3.
      const double f1 = k3 - k2, f2 = k1 - k3, f3 = k2 - k1;
      const double Kx = f1 * ax + f2 * bx + f3 * cx;
      const double Ky = f1 * ay + f2 * by + f3 * cy;
      const double Kz = f1 * az + f2 * bz + f3 * cz;
      const double W = o1 + o2 + o3;
      // C_j / D, component by component (e_x × K = (0, −K_z, K_y), ...).
      const double cxx = (k1x * n1x + k2x * n2x + k3x * n3x + W) * iD;
      const double cxy = (k1x * n1y + k2x * n2y + k3x * n3y - Kz) * iD;
      const double cxz = (k1x * n1z + k2x * n2z + k3x * n3z + Ky) * iD;
      const double cyx = (k1y * n1x + k2y * n2x + k3y * n3x + Kz) * iD;
      const double cyy = (k1y * n1y + k2y * n2y + k3y * n3y + W) * iD;
      const double cyz = (k1y * n1z + k2y * n2z + k3y * n3z - Kx) * iD;
      const double czx = (k1z * n1x + k2z * n2x + k3z * n3x - Ky) * iD;
      const double czy = (k1z * n1y + k2z * n2y + k3z * n3y + Kx) * iD;
      const double czz = (k1z * n1z + k2z * n2z + k3z * n3z + W) * iD;
      const auto grad = [&](double nx, double ny, double nz, double* gx, double* gy, double* gz) {
        gx[p] += nx * cxx + ny * cxy + nz * cxz;
        gy[p] += nx * cyx + ny * cyy + nz * cyz;
        gz[p] += nx * czx + ny * czy + nz * czz;
      };
      grad(n1x, n1y, n1z, g1x, g1y, g1z);
      grad(n2x, n2y, n2z, g2x, g2y, g2z);
      grad(n3x, n3y, n3z, g3x, g3y, g3z);
    }
  }
}

/// Output rows the caller writes after the next block (one matrix, or four
/// with gradients, of column stride `stride`: B values at base[j] + v * stride
/// for column v): the kernel prefetches their lines while it computes,
/// `per_step` rows after each triangle, so that the caller's stores do not wait
/// for memory (outputs of a few thousand points are larger than L2).
struct PolyhedronPrefetch {
  double* base[4] = {};
  long stride = 0;
  int rows = 0, per_step = 0;
};

/// Accumulates the weights (and gradients) of `cnt` points (normalized, in
/// s.px/py/pz) into the weight rows of s, and sets s.flag[p] for points that
/// need the robust path; prefetches `next` if given.
template <bool kGrad>
WARPFEM_KERNEL_INLINE void polyhedron_block(const PolyhedronArrays& P, int cnt, PolyhedronScratch& s,
                                            const PolyhedronPrefetch* next = nullptr) {
  const double *vx = P.x.data(), *vy = P.y.data(), *vz = P.z.data();
  const int n = static_cast<int>(P.size()), m = static_cast<int>(P.triangle_count());
  constexpr int B = kPolyhedronBlock;
  // The block is padded with copies of its first point, so that every loop
  // runs over all B points: a fixed trip count, no remainder loops.
  for (int p = cnt; p < B; ++p) s.px[p] = s.px[0], s.py[p] = s.py[0], s.pz[p] = s.pz[0];
  for (int p = 0; p < B; ++p) s.flag[p] = s.plane[p] = s.plane_face[p] = 0.0;
  for (int v = 0; v < n; ++v) {
    double* __restrict sx = s.vertex_row(v, 0);
    double* __restrict sy = s.vertex_row(v, 1);
    double* __restrict sz = s.vertex_row(v, 2);
    double* __restrict r = s.vertex_row(v, 3);
    double* __restrict flag = s.flag;
    const double ax = vx[v], ay = vy[v], az = vz[v];
    WARPFEM_IVDEP
    for (int p = 0; p < B; ++p) {
      const double x = ax - s.px[p], y = ay - s.py[p], z = az - s.pz[p];
      const double r2 = x * x + y * y + z * z;
      sx[p] = x;
      sy[p] = y;
      sz[p] = z;
      r[p] = std::sqrt(r2);
      flag[p] = r[p] < kPolyhedronNearVertex ? 1.0 : flag[p];
    }
    for (int row = 0; row < (kGrad ? 4 : 1); ++row) {
      double* __restrict w = s.weight_row(v, row);
      for (int p = 0; p < B; ++p) w[p] = 0.0;
    }
  }
  // Triangles in P.order; before each, the edges it is the first to use (each
  // edge's terms serve both of its triangles, up to the sign of N).
  for (int i = 0; i < m; ++i) {
    for (int j = P.edge_first[i]; j < P.edge_first[i + 1]; ++j) {
      const int e = P.scheduled_edges[j];
      polyhedron_edge<kGrad>(s, P.edge_a[e], P.edge_b[e], P.edge_slot[e]);
    }
    polyhedron_triangle<kGrad>(P, s, P.order[i]);
    if (next) {
      constexpr int kMatrices = kGrad ? 4 : 1;
      const int end = std::min(next->rows, (i + 1) * next->per_step);
      for (int r = i * next->per_step; r < end; ++r) {
        const double* row = next->base[r % kMatrices] + (r / kMatrices) * next->stride;
        __builtin_prefetch(row, 1, 2);
        __builtin_prefetch(row + B / 2, 1, 2);
        __builtin_prefetch(row + B - 1, 1, 2);
      }
    }
  }
}

}  // namespace warpfem::mapping::detail
