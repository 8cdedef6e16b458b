#include "mapping/mean_value_certificate.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/composite_mean_value_map.hpp"

namespace warpfem::mapping {
namespace {

// Interval_nt<false> assumes the FPU rounds upward; every enclosure runs under
// a Protect_FPU_rounding guard that sets and restores the mode.
using I = CGAL::Interval_nt<false>;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

/// An interval with its gradient g (x, y), Hessian h (xx, xy, yy) and, for
/// Order 3, third derivatives t (xxx, xxy, xyy, yyy): forward differentiation
/// in x and y. A mixed derivative is indexed by its number of y's (h[i + j],
/// t[i + j + k] for directions i, j, k ∈ {0 = x, 1 = y}).
template <int Order>
struct Jet {
  static_assert(Order == 2 || Order == 3);
  static constexpr int kThird = Order == 3 ? 4 : 0;
  I v, g[2], h[3];
  std::array<I, kThird> t = zero_third();

  static std::array<I, kThird> zero_third() {
    std::array<I, kThird> z;
    z.fill(I(0));
    return z;
  }
};
template <int O>
Jet<O> constant(I v) {
  return {v, {I(0), I(0)}, {I(0), I(0), I(0)}};
}
template <int O>
Jet<O> operator+(const Jet<O>& a, const Jet<O>& b) {
  Jet<O> c{
      a.v + b.v, {a.g[0] + b.g[0], a.g[1] + b.g[1]}, {a.h[0] + b.h[0], a.h[1] + b.h[1], a.h[2] + b.h[2]}};
  for (int m = 0; m < Jet<O>::kThird; ++m) c.t[m] = a.t[m] + b.t[m];
  return c;
}
template <int O>
Jet<O> operator-(const Jet<O>& a, const Jet<O>& b) {
  Jet<O> c{
      a.v - b.v, {a.g[0] - b.g[0], a.g[1] - b.g[1]}, {a.h[0] - b.h[0], a.h[1] - b.h[1], a.h[2] - b.h[2]}};
  for (int m = 0; m < Jet<O>::kThird; ++m) c.t[m] = a.t[m] - b.t[m];
  return c;
}
template <int O>
Jet<O> operator*(double s, const Jet<O>& a) {
  Jet<O> c{s * a.v, {s * a.g[0], s * a.g[1]}, {s * a.h[0], s * a.h[1], s * a.h[2]}};
  for (int m = 0; m < Jet<O>::kThird; ++m) c.t[m] = s * a.t[m];
  return c;
}
template <int O>
Jet<O> operator*(const I& s, const Jet<O>& a) {
  Jet<O> c{s * a.v, {s * a.g[0], s * a.g[1]}, {s * a.h[0], s * a.h[1], s * a.h[2]}};
  for (int m = 0; m < Jet<O>::kThird; ++m) c.t[m] = s * a.t[m];
  return c;
}
/// The directions (i, j, k), i ≤ j ≤ k, of t[m]: m of them are y.
constexpr int kTriple[4][3] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 1, 1}};
template <int O>
Jet<O> operator*(const Jet<O>& a, const Jet<O>& b) {
  Jet<O> c{a.v * b.v,
           {a.g[0] * b.v + a.v * b.g[0], a.g[1] * b.v + a.v * b.g[1]},
           {a.h[0] * b.v + 2 * (a.g[0] * b.g[0]) + a.v * b.h[0],
            a.h[1] * b.v + a.g[0] * b.g[1] + a.g[1] * b.g[0] + a.v * b.h[1],
            a.h[2] * b.v + 2 * (a.g[1] * b.g[1]) + a.v * b.h[2]}};
  for (int m = 0; m < Jet<O>::kThird; ++m) {  // Leibniz: the 8 ways to split {i, j, k} between a and b
    const int i = kTriple[m][0], j = kTriple[m][1], k = kTriple[m][2];
    c.t[m] = a.t[m] * b.v + a.h[i + j] * b.g[k] + a.h[i + k] * b.g[j] + a.h[j + k] * b.g[i] +
             a.g[i] * b.h[j + k] + a.g[j] * b.h[i + k] + a.g[k] * b.h[i + j] + a.v * b.t[m];
  }
  return c;
}
template <int O>
Jet<O> reciprocal(const Jet<O>& b) {
  // The chain rule with (1/b)' = −1/b², (1/b)'' = 2/b³, (1/b)''' = −6/b⁴.
  const I i = 1 / b.v, i2 = CGAL::square(i), i3 = i2 * i;
  Jet<O> c{i,
           {-b.g[0] * i2, -b.g[1] * i2},
           {2 * CGAL::square(b.g[0]) * i3 - b.h[0] * i2, 2 * (b.g[0] * b.g[1]) * i3 - b.h[1] * i2,
            2 * CGAL::square(b.g[1]) * i3 - b.h[2] * i2}};
  if constexpr (O == 3) {
    const I i4 = CGAL::square(i2);
    for (int m = 0; m < 4; ++m) {
      const int x = kTriple[m][0], y = kTriple[m][1], z = kTriple[m][2];
      c.t[m] = -6 * (b.g[x] * b.g[y] * b.g[z]) * i4 +
               2 * (b.h[x + y] * b.g[z] + b.h[x + z] * b.g[y] + b.h[y + z] * b.g[x]) * i3 - b.t[m] * i2;
    }
  }
  return c;
}
template <int O>
Jet<O> operator/(const Jet<O>& a, const Jet<O>& b) {
  return a * reciprocal(b);
}

I clamp_unit(const I& a) {  // a cosine or sine: [-1, 1] is always valid
  return I(std::max(a.inf(), -1.0), std::min(a.sup(), 1.0));
}

/// Edges whose A varies by more than this ratio over a box are treated as touching it.
constexpr Real kNearRatio = 0.5;
/// Edges seen under an angle α with tan(α/2) above this dominate the weights
/// of their vertices; they are scaled out too, so the quotient w / Σ w does not
/// carry their (large, wide) t_k in both numerator and denominator.
constexpr Real kNearTan = 4;

/// t = tan(α/2) of an edge seen under the angle α, from A (cross product), P
/// (r_k r_{k+1}) and D (dot product of d_k and d_{k+1}): A / (P + D) for edges
/// seen under less than 90°, the equal (P − D) / A otherwise, so no denominator
/// suffers cancellation. Unless A is then well away from 0 (relative to its
/// width), the cell is at or close to the segment: t = P − D, and the function
/// returns true (the edge is near; the caller scales every weight by A).
template <int O>
bool half_angle_tangent(const Jet<O>& A, const Jet<O>& P, const Jet<O>& D, Jet<O>& t) {
  if (D.v.sup() >= 0) {
    t = A / (P + D);
    return false;
  }
  const Real lo = std::min(std::abs(A.v.inf()), std::abs(A.v.sup()));
  const Real hi = std::max(std::abs(A.v.inf()), std::abs(A.v.sup()));
  t = P - D;
  if ((A.v.inf() > 0 || A.v.sup() < 0) && lo > kNearRatio * hi && t.v.inf() < kNearTan * hi) {
    t = t / A;
    return false;
  }
  return true;
}

/// Multiplies every t_k by `scale` (the product of the near edges' A), a near
/// edge's by the other near edges' A only (its own is in its t = P − D):
/// φ = w / Σ w is unchanged.
template <int O>
void scale_out_near_edges(Index n, Jet<O>* t, const Jet<O>* area, const std::vector<char>& near,
                          const Jet<O>& scale) {
  for (Index k = 0; k < n; ++k) {
    if (!near[static_cast<std::size_t>(k)]) {
      t[k] = t[k] * scale;
      continue;
    }
    for (Index e = 0; e < n; ++e)
      if (e != k && near[static_cast<std::size_t>(e)]) t[k] = t[k] * area[e];
  }
}

/// One step's data: the polygon P_k and the vertex displacements u_i.
struct StepData {
  const Polygon& polygon;
  const std::vector<Real>& ux;
  const std::vector<Real>& uy;
};

/// The displacement minus a constant, Q = Σ φ_j (u_j − ū), over the box X × Y
/// (a point when the intervals are thin), from the mean value weights
///   w_j = (t_{j−1} + t_j) / r_j,  t_k = tan(α_k / 2),
/// with t_k = A_k / (P_k + D_k) (A: cross, D: dot of d_k = v_k − x and d_{k+1},
/// P = r_k r_{k+1}) for edges seen under less than 90°, and the equal
/// t_k = (P_k − D_k) / A_k otherwise, so no denominator suffers cancellation.
/// Where A_k may vanish (the box touches edge k) every weight is multiplied by
/// A_k instead (φ = w / Σ w is unchanged), which extends the formula smoothly
/// over the part of a boundary cell outside P_k. Returns false if Σ w may vanish.
template <int O>
bool displacement_jets(const StepData& s, const I& X, const I& Y, double bx, double by, Jet<O>& Qx,
                       Jet<O>& Qy, std::vector<Jet<O>>& buf, std::vector<char>& near) {
  using J = Jet<O>;
  const Index n = s.polygon.size();
  buf.resize(static_cast<std::size_t>(4 * n));
  J* r = buf.data();
  J* t = r + n;
  J* area = t + n;
  J* inv_r = area + n;
  for (Index i = 0; i < n; ++i) {
    const Point<2>& v = s.polygon.vertex(i);
    const I ex = v.x() - X, ey = v.y() - Y;
    const I len = CGAL::sqrt(CGAL::square(ex) + CGAL::square(ey));
    const I c = clamp_unit(-ex / len), sn = clamp_unit(-ey / len);
    // r = |x − v_i| and 1/r with their derivatives in closed form (n = ∇r =
    // (c, sn)), so the cancellations inside them are exact, not left to the
    // interval arithmetic of a quotient rule.
    const I c2 = CGAL::square(c), s2 = CGAL::square(sn), cs = c * sn;
    const I len2 = CGAL::square(len), len3 = len2 * len;
    r[i] = {len, {c, sn}, {s2 / len, -cs / len, c2 / len}};
    inv_r[i] = {1 / len, {-c / len2, -sn / len2}, {(3 * c2 - 1) / len3, 3 * cs / len3, (3 * s2 - 1) / len3}};
    if constexpr (O == 3) {
      // ∂³r = −(δ_ij n_k + δ_ik n_j + δ_jk n_i − 3 n_i n_j n_k) / r²,
      // ∂³(1/r) = (3 (δ_ij n_k + δ_ik n_j + δ_jk n_i) − 15 n_i n_j n_k) / r⁴.
      r[i].t = {-3 * (c * s2) / len2, -(sn * (1 - 3 * c2)) / len2, -(c * (1 - 3 * s2)) / len2,
                -3 * (sn * c2) / len2};
      const I len4 = CGAL::square(len2);
      inv_r[i].t = {-3 * (c * (5 * c2 - 3)) / len4, -3 * (sn * (5 * c2 - 1)) / len4,
                    -3 * (c * (5 * s2 - 1)) / len4, -3 * (sn * (5 * s2 - 3)) / len4};
    }
  }
  near.assign(static_cast<std::size_t>(n), 0);
  J scale = constant<O>(I(1));
  for (Index k = 0; k < n; ++k) {
    const Index k1 = (k + 1) % n;
    // A (affine in x) and D (a shifted square) in forms where x occurs once,
    // so their enclosures are tight.
    const Point<2>& a = s.polygon.vertex(k);
    const Point<2>& b = s.polygon.vertex(k1);
    const I exv = I(b.x()) - a.x(), eyv = I(b.y()) - a.y();
    const J& A =
        area[k] = {I(a.x()) * b.y() - I(a.y()) * b.x() + exv * Y - eyv * X, {-eyv, exv}, {I(0), I(0), I(0)}};
    const I mx = (I(a.x()) + b.x()) / 2, my = (I(a.y()) + b.y()) / 2;
    const J D{CGAL::square(X - mx) + CGAL::square(Y - my) - (CGAL::square(exv) + CGAL::square(eyv)) / 4,
              {2 * (X - mx), 2 * (Y - my)},
              {I(2), I(0), I(2)}};
    const J P = r[k] * r[k1];
    if (half_angle_tangent(A, P, D, t[k])) {
      near[static_cast<std::size_t>(k)] = 1;
      scale = scale * A;
    }
  }
  scale_out_near_edges(n, t, area, near, scale);
  const auto u = [&](const std::vector<Real>& v, Index j) { return v[static_cast<std::size_t>(j)]; };
  J W = constant<O>(I(0)), Ux = W, Uy = W;
  for (Index j = 0; j < n; ++j) {
    const J w = (t[(j + n - 1) % n] + t[j]) * inv_r[j];
    W = W + w;
    Ux = Ux + (u(s.ux, j) - bx) * w;
    Uy = Uy + (u(s.uy, j) - by) * w;
  }
  if (!(W.v.inf() > 0 || W.v.sup() < 0)) return false;
  const J iW = reciprocal(W);
  Qx = Ux * iW;
  Qy = Uy * iW;
  return true;
}

I hull(const I& a, const I& b) {
  return I(std::min(a.inf(), b.inf()), std::max(a.sup(), b.sup()));
}
/// The intersection of two enclosures of the same range, or `fallback` when
/// they do not overlap (which rounding alone cannot cause) or `a` has a NaN
/// end (a NaN end of `b` gives `a`).
I meet(const I& a, const I& b, const I& fallback) {
  const double lo = std::max(a.inf(), b.inf()), hi = std::min(a.sup(), b.sup());
  return lo <= hi ? I(lo, hi) : fallback;
}

/// The Taylor model is tried on a cell only while the entry-wise interval is
/// at most this many times det J_k at its centre.
constexpr Real kTaylorWidthRatio = 4;

/// Per-thread buffers of the enclosures.
struct Workspace {
  std::vector<Jet<2>> centre;
  std::vector<Jet<2>> box2;
  std::vector<Jet<3>> box3;
  std::vector<char> near;
};

/// Encloses det J_k over the box [x0, x1] × [y0, y1]. (1) Each entry of
/// J_k − I, a first derivative of Q, by its centred form (value at the centre
/// c plus the Hessian over the box times the half-widths) met with its direct
/// enclosure over the box. If the lower end is below `good_enough`: (2) det J_k
/// by a second-order Taylor model around c, met with (1) (on a `last_try`
/// always, otherwise only where (1) is not far too wide for it). With every entry
/// e = e(c) + ∇e(c)·δ + R_e (R_e from the third derivatives over the box),
/// det J_k is its value at c, plus a term linear in δ whose range is exact,
/// plus terms of order |δ|². (1) loses the cancellation inside the determinant
/// and overestimates the Hessian over the box by a factor that grows toward a
/// vertex; (2) is tight to O(|δ|²), at about twice the cost, and lets cells
/// near a vertex be larger. The FPU must round upward.
I det_enclosure(const StepData& s, Real x0, Real x1, Real y0, Real y1, Real good_enough, bool last_try,
                Workspace& ws) {
  const Real cx = x0 / 2 + x1 / 2, cy = y0 / 2 + y1 / 2;
  Jet<2> Cx, Cy;
  if (!displacement_jets(s, I(cx), I(cy), 0, 0, Cx, Cy, ws.centre, ws.near)) return I::largest();
  // Over the box, ū = the displacement at the centre (any constant is valid;
  // this one keeps the quotient rule's terms small).
  const double bx = Cx.v.inf() / 2 + Cx.v.sup() / 2, by = Cy.v.inf() / 2 + Cy.v.sup() / 2;
  const I box_x(x0, x1), box_y(y0, y1);
  Jet<2> Bx, By;
  if (!displacement_jets(s, box_x, box_y, bx, by, Bx, By, ws.box2, ws.near)) return I::largest();
  const I hx = hull(I(x0) - cx, I(x1) - cx), hy = hull(I(y0) - cy, I(y1) - cy);

  auto entry = [&](const Jet<2>& centre, const Jet<2>& box, int j) {  // ∂Q/∂x_j over the box
    const I centred = centre.g[j] + box.h[j] * hx + box.h[j + 1] * hy;
    return meet(centred, box.g[j], centred);
  };
  const I a = entry(Cx, Bx, 0), b = entry(Cx, Bx, 1), c = entry(Cy, By, 0), d = entry(Cy, By, 1);
  const I by_entries = (1 + a) * (1 + d) - b * c;
  if (by_entries.inf() >= good_enough) return by_entries;
  // Where (1) is many times wider than det J_k at the centre, the cell is too
  // large for (2) as well (its remainder grows faster with the cell): it is
  // split without trying.
  const I at_centre = (1 + Cx.g[0]) * (1 + Cy.g[1]) - Cx.g[1] * Cy.g[0];
  if (!last_try && by_entries.sup() - by_entries.inf() > kTaylorWidthRatio * CGAL::abs(at_centre).inf())
    return by_entries;

  Jet<3> Tx, Ty;
  if (!displacement_jets(s, box_x, box_y, bx, by, Tx, Ty, ws.box3, ws.near)) return by_entries;
  // ∂Q/∂x_j = e0 + e1·δ + R over the box: value and gradient at the centre,
  // R = ½ δᵀ (∇²e over the box) δ.
  struct Expansion {
    I e0, e1[2], linear, rest;
  };
  const I hx2 = CGAL::square(hx), hy2 = CGAL::square(hy), hxy = hx * hy;
  auto expand = [&](const Jet<2>& centre, const Jet<3>& box, int j) {
    Expansion e{centre.g[j], {centre.h[j], centre.h[j + 1]}, I(0), I(0)};
    e.linear = e.e1[0] * hx + e.e1[1] * hy;
    e.rest = (box.t[j] * hx2 + 2 * (box.t[j + 1] * hxy) + box.t[j + 2] * hy2) / 2;
    return e;
  };
  const Expansion ea = expand(Cx, Tx, 0), eb = expand(Cx, Tx, 1), ec = expand(Cy, Ty, 0),
                  ed = expand(Cy, Ty, 1);
  const I pa = 1 + ea.e0, pd = 1 + ed.e0;
  I gradient[2];
  for (int i = 0; i < 2; ++i)
    gradient[i] = pa * ed.e1[i] + pd * ea.e1[i] - eb.e0 * ec.e1[i] - ec.e0 * eb.e1[i];
  const I quadratic = pa * ed.rest + pd * ea.rest - eb.e0 * ec.rest - ec.e0 * eb.rest +
                      (ea.linear + ea.rest) * (ed.linear + ed.rest) -
                      (eb.linear + eb.rest) * (ec.linear + ec.rest);
  const I by_taylor = at_centre + gradient[0] * hx + gradient[1] * hy + quadratic;

  return meet(by_entries, by_taylor, I::largest());
}

/// √u with the chain rule: with v = √u, ∂v = ∂u / (2v), ∂²v = ∂²u / (2v) −
/// ∂u ∂uᵀ / (4 v³), and ∂³v = ∂³u / (2v) − 3 sym(∂²u ⊗ ∂u) / (4 v³) +
/// 3 ∂u ⊗ ∂u ⊗ ∂u / (8 v⁵).
template <int O>
Jet<O> sqrt_jet(const Jet<O>& u) {
  const I v = CGAL::sqrt(u.v), half = 1 / (2 * v), quarter = half / (2 * u.v);
  Jet<O> c{v,
           {u.g[0] * half, u.g[1] * half},
           {u.h[0] * half - CGAL::square(u.g[0]) * quarter, u.h[1] * half - (u.g[0] * u.g[1]) * quarter,
            u.h[2] * half - CGAL::square(u.g[1]) * quarter}};
  if constexpr (O == 3) {
    const I eighth = 3 * quarter / (2 * u.v);
    for (int m = 0; m < 4; ++m) {
      const int i = kTriple[m][0], j = kTriple[m][1], k = kTriple[m][2];
      c.t[m] = u.t[m] * half - (u.h[i + j] * u.g[k] + u.h[i + k] * u.g[j] + u.h[j + k] * u.g[i]) * quarter +
               (u.g[i] * u.g[j] * u.g[k]) * eighth;
    }
  }
  return c;
}

/// cos and sin over [t0, t1] (t1 − t0 < π): the libm's values, computed in
/// round-to-nearest (where glibc's are within an ulp) and widened by two ulps
/// at each end; an extremum inside the range (or within 1e-12 of it) widens
/// that end to ±1.
void cos_sin(Real t0, Real t1, I& c, I& s) {
  const auto widen = [](Real a, Real b) {
    return I(std::nextafter(std::nextafter(std::min(a, b), -2.0), -2.0),
             std::nextafter(std::nextafter(std::max(a, b), 2.0), 2.0));
  };
  Real c0, c1, s0, s1;
  {
    CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);
    c0 = std::cos(t0), c1 = std::cos(t1), s0 = std::sin(t0), s1 = std::sin(t1);
  }
  c = widen(c0, c1);
  s = widen(s0, s1);
  const auto holds = [&](Real phase) {  // some phase + 2kπ in [t0, t1]?
    constexpr Real two_pi = 2 * std::numbers::pi, pad = 1e-12;
    return std::floor((t1 + pad - phase) / two_pi) >= std::ceil((t0 - pad - phase) / two_pi);
  };
  if (holds(0)) c = I(c.inf(), 1);
  if (holds(std::numbers::pi)) c = I(-1, c.sup());
  if (holds(std::numbers::pi / 2)) s = I(s.inf(), 1);
  if (holds(-std::numbers::pi / 2)) s = I(-1, s.sup());
  c = clamp_unit(c);
  s = clamp_unit(s);
}

/// A jet of value and gradient only.
struct Jet1 {
  I v, g[2];
};
Jet1 operator+(const Jet1& a, const Jet1& b) {
  return {a.v + b.v, {a.g[0] + b.g[0], a.g[1] + b.g[1]}};
}
Jet1 operator-(const Jet1& a, const Jet1& b) {
  return {a.v - b.v, {a.g[0] - b.g[0], a.g[1] - b.g[1]}};
}
Jet1 operator*(const Jet1& a, const Jet1& b) {
  return {a.v * b.v, {a.g[0] * b.v + a.v * b.g[0], a.g[1] * b.v + a.v * b.g[1]}};
}

/// In polar coordinates x = v_p + ρ n(θ) around vertex p, Q = Σ φ_j (u_j − u_p)
/// = ρ G(ρ, θ) with G smooth up to ρ = 0 inside the corner: G =
/// Σ_{j≠p} w_j (u_j − u_p) / (ρ W), ρ W = t_{p−1} + t_p + ρ Σ_{j≠p} w_j, where
/// t_{p−1}, t_p are homogeneous of degree 0 in d_p = v_p − x = −ρ n, so they are
/// computed with d_p = −n and r_p = 1. G's jets in (ρ, θ) over [ρ0, ρ1] ×
/// [θ0, θ1]. No quantity divides by ρ, so a cell may reach ρ = 0. Returns false
/// if ρ W may vanish.
template <int O>
bool polar_jets(const StepData& s, Index p, const I& rho, const I& cosine, const I& sine, Jet<O>& Gx,
                Jet<O>& Gy, std::vector<Jet<O>>& buf, std::vector<char>& near) {
  using J = Jet<O>;
  const Index n = s.polygon.size();
  buf.resize(static_cast<std::size_t>(3 * n));
  J* r = buf.data();
  J* t = r + n;
  J* area = t + n;
  const J R{rho, {I(1), I(0)}, {I(0), I(0), I(0)}};
  J C{cosine, {I(0), -sine}, {I(0), I(0), -cosine}};
  J S{sine, {I(0), cosine}, {I(0), I(0), -sine}};
  if constexpr (O == 3) {  // ∂³/∂θ³ of cos and sin
    C.t[3] = sine;
    S.t[3] = -cosine;
  }
  // With a_j = v_j − v_p and w = x − v_p = ρ n, d_j = a_j − w. Every product of
  // two d's is expanded so that x enters through w and |w|² = ρ² only (n·n = 1
  // exactly): cheaper, and tighter than multiplying jets of d.
  const J Wx = R * C, Wy = R * S, R2 = R * R;
  const Point<2>& vp = s.polygon.vertex(p);
  const auto a = [&](Index j) {
    const Point<2>& v = s.polygon.vertex(j);
    return std::pair<I, I>(I(v.x()) - vp.x(), I(v.y()) - vp.y());
  };
  for (Index j = 0; j < n; ++j) {
    if (j == p) {  // r_p / ρ
      r[j] = constant<O>(I(1));
      continue;
    }
    const auto [ax, ay] = a(j);
    r[j] = sqrt_jet(constant<O>(CGAL::square(ax) + CGAL::square(ay)) - 2 * (ax * Wx + ay * Wy) + R2);
  }
  near.assign(static_cast<std::size_t>(n), 0);
  J scale = constant<O>(I(1));
  for (Index k = 0; k < n; ++k) {
    const Index k1 = (k + 1) % n;
    const auto [bx, by] = a(k);
    const auto [cx, cy] = a(k1);
    J D;
    if (k == p) {  // d_p / ρ = −n: A = −n × a_{k1}, D = −n · a_{k1} + ρ
      area[k] = cx * S - cy * C;
      D = R - (cx * C + cy * S);
    } else if (k1 == p) {  // A = a_k × −n, D = −n · a_k + ρ
      area[k] = by * C - bx * S;
      D = R - (bx * C + by * S);
    } else {  // A = a_k × a_{k1} + (a_{k1} − a_k) × w, D = a_k · a_{k1} − (a_k + a_{k1}) · w + ρ²
      area[k] = constant<O>(bx * cy - by * cx) + (cx - bx) * Wy - (cy - by) * Wx;
      D = constant<O>(bx * cx + by * cy) - ((bx + cx) * Wx + (by + cy) * Wy) + R2;
    }
    const J& A = area[k];
    const J P = k == p ? r[k1] : k1 == p ? r[k] : r[k] * r[k1];
    if (half_angle_tangent(A, P, D, t[k])) {
      near[static_cast<std::size_t>(k)] = 1;
      scale = scale * A;
    }
  }
  scale_out_near_edges(n, t, area, near, scale);
  const Real upx = s.ux[static_cast<std::size_t>(p)], upy = s.uy[static_cast<std::size_t>(p)];
  J rest = constant<O>(I(0)), Nx = rest, Ny = rest;
  for (Index j = 0; j < n; ++j) {
    if (j == p) continue;
    const J w = (t[(j + n - 1) % n] + t[j]) / r[j];
    rest = rest + w;
    Nx = Nx + (s.ux[static_cast<std::size_t>(j)] - upx) * w;
    Ny = Ny + (s.uy[static_cast<std::size_t>(j)] - upy) * w;
  }
  const J rhoW = t[(p + n - 1) % n] + t[p] + R * rest;
  if (!(rhoW.v.inf() > 0 || rhoW.v.sup() < 0)) return false;
  const J inv = reciprocal(rhoW);
  Gx = Nx * inv;
  Gy = Ny * inv;
  return true;
}

/// With a = G + ρ G_ρ and b = G_θ, J_k = I + a nᵀ + b n⊥ᵀ (n⊥ = (−n_y, n_x)),
/// so det J_k = 1 + a·n + b·n⊥ + a × b; for jets J of any order in (ρ, θ).
template <typename J>
J corner_det(const J& one, const J& ax, const J& ay, const J& bx, const J& by, const J& nx, const J& ny) {
  return one + ax * nx + ay * ny - bx * ny + by * nx + ax * by - ay * bx;
}

/// det J_k with its gradient in (ρ, θ), from G's jets of order 2.
Jet1 polar_det(const Jet<2>& Gx, const Jet<2>& Gy, const I& rho, const I& cosine, const I& sine) {
  const auto a = [&](const Jet<2>& G) {
    return Jet1{G.v + rho * G.g[0], {2 * G.g[0] + rho * G.h[0], G.g[1] + rho * G.h[1]}};
  };
  const auto b = [](const Jet<2>& G) { return Jet1{G.g[1], {G.h[1], G.h[2]}}; };
  const Jet1 ax = a(Gx), ay = a(Gy), bx = b(Gx), by = b(Gy);
  const Jet1 nx{cosine, {I(0), -sine}}, ny{sine, {I(0), cosine}}, one{I(1), {I(0), I(0)}};
  return corner_det(one, ax, ay, bx, by, nx, ny);
}

/// det J_k with its gradient and Hessian in (ρ, θ), from G's jets of order 3
/// (a's and b's second derivatives need G's third).
Jet<2> polar_det_hessian(const Jet<3>& Gx, const Jet<3>& Gy, const I& rho, const I& cosine, const I& sine) {
  const auto a = [&](const Jet<3>& G) {
    return Jet<2>{G.v + rho * G.g[0],
                  {2 * G.g[0] + rho * G.h[0], G.g[1] + rho * G.h[1]},
                  {3 * G.h[0] + rho * G.t[0], 2 * G.h[1] + rho * G.t[1], G.h[2] + rho * G.t[2]}};
  };
  const auto b = [](const Jet<3>& G) { return Jet<2>{G.g[1], {G.h[1], G.h[2]}, {G.t[1], G.t[2], G.t[3]}}; };
  const Jet<2> ax = a(Gx), ay = a(Gy), bx = b(Gx), by = b(Gy);
  const Jet<2> nx{cosine, {I(0), -sine}, {I(0), I(0), -cosine}},
      ny{sine, {I(0), cosine}, {I(0), I(0), -sine}};
  return corner_det(constant<2>(I(1)), ax, ay, bx, by, nx, ny);
}

/// Per-thread buffers of the polar enclosures.
struct PolarWorkspace {
  std::vector<Jet<2>> second;
  std::vector<Jet<3>> third;
  std::vector<char> near;
};

/// Encloses det J_k over the polar cell [ρ0, ρ1] × [θ0, θ1] around vertex p,
/// like det_enclosure() for boxes: (1) the value at the centre plus the
/// gradient over the cell times the half-widths, met with the direct enclosure;
/// if its lower end is below `good_enough`, (2) a second-order Taylor model
/// around the centre (exact linear term, Hessian over the cell), met with (1)
/// (on a `last_try` always, otherwise only where (1) is not far too wide).
/// `spread` receives (1)'s width from ρ and from θ, so the caller can split the
/// cell in the direction that matters. The FPU must round upward.
I polar_det_enclosure(const StepData& s, Index p, Real rho0, Real rho1, Real theta0, Real theta1,
                      Real good_enough, bool last_try, PolarWorkspace& ws, Real* spread = nullptr) {
  const Real rc = rho0 / 2 + rho1 / 2, tc = theta0 / 2 + theta1 / 2;
  I cc, sc, cb, sb;
  cos_sin(tc, tc, cc, sc);
  cos_sin(theta0, theta1, cb, sb);
  Jet<2> Gx, Gy;
  if (!polar_jets(s, p, I(rc), cc, sc, Gx, Gy, ws.second, ws.near)) return I::largest();
  const Jet1 centre = polar_det(Gx, Gy, I(rc), cc, sc);
  const I box_rho(rho0, rho1);
  if (!polar_jets(s, p, box_rho, cb, sb, Gx, Gy, ws.second, ws.near)) return I::largest();
  const Jet1 box = polar_det(Gx, Gy, box_rho, cb, sb);
  const I hr = hull(I(rho0) - rc, I(rho1) - rc), ht = hull(I(theta0) - tc, I(theta1) - tc);
  const I dr = box.g[0] * hr, dt = box.g[1] * ht;
  if (spread) {
    spread[0] = dr.sup() - dr.inf();
    spread[1] = dt.sup() - dt.inf();
  }
  const I centred = centre.v + dr + dt;
  const I first = meet(centred, box.v, centred);
  if (first.inf() >= good_enough) return first;
  if (!last_try && first.sup() - first.inf() > kTaylorWidthRatio * CGAL::abs(centre.v).inf()) return first;
  Jet<3> Tx, Ty;
  if (!polar_jets(s, p, box_rho, cb, sb, Tx, Ty, ws.third, ws.near)) return first;
  const Jet<2> H = polar_det_hessian(Tx, Ty, box_rho, cb, sb);
  const I taylor = centre.v + centre.g[0] * hr + centre.g[1] * ht +
                   (H.h[0] * CGAL::square(hr) + 2 * (H.h[1] * (hr * ht)) + H.h[2] * CGAL::square(ht)) / 2;
  return meet(first, taylor, I::largest());
}

enum class CellSide { outside, inside, boundary };

CellSide classify(const Polygon& polygon, const std::vector<Kernel::Segment_2>& edges, Real x0, Real x1,
                  Real y0, Real y1) {
  const Kernel::Iso_rectangle_2 box(Kernel::Point_2(x0, y0), Kernel::Point_2(x1, y1));
  for (const auto& e : edges) {
    const auto b = e.bbox();
    if (b.xmax() < x0 || b.xmin() > x1 || b.ymax() < y0 || b.ymin() > y1) continue;
    if (CGAL::do_intersect(e, box)) return CellSide::boundary;
  }
  // No edge meets the closed box: it lies entirely on one side.
  return polygon.side_of(Point<2>(x0 / 2 + x1 / 2, y0 / 2 + y1 / 2)) > 0 ? CellSide::inside
                                                                         : CellSide::outside;
}

/// True iff the closed box lies inside the closed disk (exactly: all four
/// corners, bounded with upward-rounded interval arithmetic).
bool box_in_disk(const Point<2>& c, Real rho, Real x0, Real x1, Real y0, Real y1) {
  CGAL::Protect_FPU_rounding<true> guard;
  const I dx = CGAL::max(CGAL::abs(I(x0) - c.x()), CGAL::abs(I(x1) - c.x()));
  const I dy = CGAL::max(CGAL::abs(I(y0) - c.y()), CGAL::abs(I(y1) - c.y()));
  return (CGAL::square(dx) + CGAL::square(dy)).sup() <= (I(rho) * I(rho)).inf();
}

std::string at(Real x, Real y) {
  std::ostringstream os;
  os << std::setprecision(8) << "(" << x << ", " << y << ")";
  return os.str();
}

std::vector<Point<2>> targets_of(const Polygon& p, const std::vector<Real>& ux, const std::vector<Real>& uy) {
  std::vector<Point<2>> t;
  for (Index i = 0; i < p.size(); ++i)
    t.emplace_back(p.vertex(i).x() + ux[static_cast<std::size_t>(i)],
                   p.vertex(i).y() + uy[static_cast<std::size_t>(i)]);
  return t;
}

Real point_det(const StepData& s, Real x, Real y) {
  const BarycentricStep step(s.polygon, targets_of(s.polygon, s.ux, s.uy), Coordinates::mean_value);
  Points<2> p(1, 2), fx;
  p << x, y;
  Jacobians<2> J;
  step.apply(p, fx, &J);
  return J(0, 0) * J(0, 3) - J(0, 1) * J(0, 2);
}

[[noreturn]] void refuse(const StepData& s, Index step, Real cx, Real cy, Real size, const I& det) {
  std::ostringstream why;
  why << std::setprecision(4) << "certificate refused: step " << step << " near x = " << at(cx, cy) << ": ";
  if (det.sup() < 0)
    why << "det J_" << step << " < 0 on a cell of size " << size << " (interval [" << det.inf() << ", "
        << det.sup() << "]): the step folds there";
  else
    why << "det J_" << step << " cannot be proven positive on a cell of size " << size << " (interval ["
        << det.inf() << ", " << det.sup() << "])";
  if (s.polygon.side_of(Point<2>(cx, cy)) >= 0)
    why << "; det J_" << step << " = " << point_det(s, cx, cy) << " there";
  throw Error(why.str(),
              {.file = "",
               .key_path = "map.certify",
               .hint = "the step may fold there; use a finer partition (more steps or \"partition\": "
                       "\"adaptive\"), or \"certify\": false (sampled check only)"});
}

/// The corner of P_k at vertex p, covered by polar cells: the disk of `radius`
/// around v_p meets P_k exactly in the wedge θ ∈ [theta0, theta0 + angle]
/// between the two edges at p, because the radius is at most half of p's
/// distance to every other edge and half of both edges' lengths.
struct Sector {
  Index vertex = 0;
  Real radius = 0, theta0 = 0, angle = 0;
};

Real segment_distance(const Point<2>& x, const Point<2>& a, const Point<2>& b) {
  const Point<2> e = b - a;
  const Real t = std::clamp((x - a).dot(e) / e.squaredNorm(), Real{0}, Real{1});
  return (x - a - t * e).norm();
}

std::vector<Sector> corner_sectors(const Polygon& P) {
  const Index n = P.size();
  const bool ccw = P.signed_area() > 0;
  std::vector<Sector> sectors;
  for (Index p = 0; p < n; ++p) {
    const Point<2> v = P.vertex(p), next = P.vertex(p + 1) - v, previous = P.vertex(p - 1) - v;
    Real radius = std::min(next.norm(), previous.norm());
    for (Index k = 0; k < n; ++k)
      if (k != p && P.wrap(k + 1) != p)
        radius = std::min(radius, segment_distance(v, P.vertex(k), P.vertex(k + 1)));
    // The interior is left of the edges of a counter-clockwise polygon: from
    // the outgoing edge counter-clockwise to the incoming one.
    const Point<2> from = ccw ? next : previous, to = ccw ? previous : next;
    Real angle = std::atan2(from.x() * to.y() - from.y() * to.x(), from.dot(to));
    if (angle <= 0) angle += 2 * std::numbers::pi;
    // Widened by 1e-9 on both sides: the rays' directions are rounded; the
    // enclosure extends smoothly over the edges (their areas are scaled out).
    sectors.push_back({p, radius / 2, std::atan2(from.y(), from.x()) - 1e-9, angle + 2e-9});
  }
  return sectors;
}

/// The least det J_k at the points of a grid × grid lattice over P_k's
/// bounding box that lie inside P_k, and at points of every corner sector from
/// 1e-6 to 0.9 of its radius (+∞ if none): an upper bound of the minimum the
/// certificate bounds from below.
Real sampled_min_det(const StepData& s, const std::vector<Sector>& sectors, int grid) {
  const Polygon& P = s.polygon;
  const Point<2> lo = P.bbox_min(), hi = P.bbox_max();
  std::vector<Point<2>> inside;
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const Point<2> x(lo.x() + (hi.x() - lo.x()) * (i + 0.5) / grid,
                       lo.y() + (hi.y() - lo.y()) * (j + 0.5) / grid);
      if (P.side_of(x) > 0) inside.push_back(x);
    }
  constexpr int kRays = 32;
  for (const Sector& c : sectors)
    for (const Real fraction : {1e-6, 1e-3, 0.03, 0.3, 0.9})
      for (int a = 0; a < kRays; ++a) {
        const Real t = c.theta0 + c.angle * (a + 0.5) / kRays;
        const Point<2> x = P.vertex(c.vertex) + fraction * c.radius * Point<2>(std::cos(t), std::sin(t));
        if (P.side_of(x) > 0) inside.push_back(x);
      }
  if (inside.empty()) return std::numeric_limits<Real>::infinity();
  Points<2> x(static_cast<Index>(inside.size()), 2), fx;
  for (Index p = 0; p < x.rows(); ++p) x.row(p) = inside[static_cast<std::size_t>(p)].transpose();
  const BarycentricStep step(P, targets_of(P, s.ux, s.uy), Coordinates::mean_value);
  Jacobians<2> J;
  step.apply(x, fx, &J);
  Real m = std::numeric_limits<Real>::infinity();
  for (Index p = 0; p < x.rows(); ++p) m = std::min(m, J(p, 0) * J(p, 3) - J(p, 1) * J(p, 2));
  return m;
}

/// Certifies det J_k on one corner sector with an adaptive bisection of polar
/// cells [ρ0, ρ1] × [θ0, θ1], each split in the direction (ρ or θ) that
/// contributes more to its interval's width.
template <typename Count, typename Refuse>
void certify_sector(const StepData& s, const Sector& sector, Real tight_enough, Real stops_at,
                    Real min_fraction, StepCertificate& part, PolarWorkspace& ws, const Count& count_cell,
                    const Refuse& refuse_at) {
  struct Cell {
    Real r0, r1, t0, t1;
  };
  const int pieces = static_cast<int>(std::ceil(sector.angle / (std::numbers::pi / 8)));
  std::vector<Cell> stack;
  for (int i = 0; i < pieces; ++i)
    stack.push_back({0, sector.radius, sector.theta0 + sector.angle * i / pieces,
                     sector.theta0 + sector.angle * (i + 1) / pieces});
  const Real min_size = min_fraction * sector.radius, min_angle = min_fraction * sector.angle;
  const Point<2>& v = s.polygon.vertex(sector.vertex);
  while (!stack.empty()) {
    const Cell c = stack.back();
    stack.pop_back();
    Real spread[2] = {0, 0};
    const bool split_rho = (c.r1 - c.r0) / 2 >= min_size, split_theta = (c.t1 - c.t0) / 2 >= min_angle;
    I det;
    {
      CGAL::Protect_FPU_rounding<true> guard;
      det = polar_det_enclosure(s, sector.vertex, c.r0, c.r1, c.t0, c.t1, stops_at,
                                /*last_try=*/!split_rho && !split_theta, ws, spread);
    }
    ++part.cells;
    count_cell();
    // Tightening (as for the quadtree) stops at 1/64 of the radius and 1/256 of the angle.
    const bool may_tighten = c.r1 - c.r0 > sector.radius / 64 || c.t1 - c.t0 > sector.angle / 256;
    const bool loose = det.inf() < tight_enough && may_tighten;
    if (det.inf() > 0 && !loose) {
      if (det.inf() < part.lower_bound) {
        part.lower_bound = det.inf();
        const Real r = c.r0 / 2 + c.r1 / 2, t = c.t0 / 2 + c.t1 / 2;
        part.lower_bound_at = v + r * Point<2>(std::cos(t), std::sin(t));
      }
      continue;
    }
    // An enclosure that failed (ρ W may vanish) says nothing about the widths:
    // then the side longer relative to the sector's is split.
    const bool failed = !std::isfinite(det.inf()) || !std::isfinite(det.sup());
    const bool rho_first = failed ? (c.r1 - c.r0) / sector.radius >= (c.t1 - c.t0) / (std::numbers::pi / 8)
                                  : spread[0] >= spread[1];
    if (split_rho && (!split_theta || rho_first)) {
      const Real m = c.r0 / 2 + c.r1 / 2;
      stack.push_back({c.r0, m, c.t0, c.t1});
      stack.push_back({m, c.r1, c.t0, c.t1});
    } else if (split_theta) {
      const Real m = c.t0 / 2 + c.t1 / 2;
      stack.push_back({c.r0, c.r1, c.t0, m});
      stack.push_back({c.r0, c.r1, m, c.t1});
    } else {
      const Real r = c.r0 / 2 + c.r1 / 2, t = c.t0 / 2 + c.t1 / 2;
      refuse_at(v + r * Point<2>(std::cos(t), std::sin(t)), c.r1 - c.r0, det);
    }
  }
}

StepCertificate certify_step(const StepData& s, const CertifyOptions& o, Index step) {
  const Polygon& P = s.polygon;
  const Point<2> lo = P.bbox_min(), hi = P.bbox_max();
  const Real diam = (hi - lo).norm();
  StepCertificate c;
  const std::vector<Sector> sectors = corner_sectors(P);
  // Cells whose lower end is already above tightness × the sampled minimum
  // do not decide b_k: they stop at their first positive interval. (A
  // sampled minimum ≤ 0 means the step folds; the cells then find where.)
  const Real sampled = o.tightness > 0 ? sampled_min_det(s, sectors, o.sample_grid) : 0;
  const Real tight_enough = std::isfinite(sampled) ? o.tightness * std::max(sampled, Real{0}) : 0;
  c.lower_bound = std::numeric_limits<Real>::infinity();
  const Real min_size = o.min_cell_fraction * diam;
  std::vector<Kernel::Segment_2> edges;
  for (Index i = 0; i < P.size(); ++i)
    edges.emplace_back(Kernel::Point_2(P.vertex(i).x(), P.vertex(i).y()),
                       Kernel::Point_2(P.vertex(i + 1).x(), P.vertex(i + 1).y()));
  const Real side = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  struct Cell {
    Real x0, y0, h;
  };
  // The quadtree's first levels as independent roots, processed in parallel
  // (each thread with its own rounding-mode guard and buffers).
  constexpr int kRoots = 8;
  // A lower end at or above this stops every cell, so the second enclosure is
  // computed only below it.
  const Real stops_at = std::max(tight_enough, std::numeric_limits<Real>::denorm_min());
  std::atomic<Index> total_cells{0};
  const auto count_cell = [&] {
    if (++total_cells > o.max_cells)
      throw Error("certificate: step " + std::to_string(step) + " needs more than " +
                      std::to_string(o.max_cells) + " cells",
                  {.file = "",
                   .key_path = "map.certify",
                   .hint = "use a finer partition (more steps), or \"certify\": false (sampled check only)"});
  };
  // The corners first (polar cells), then the rest of P_k (a quadtree whose
  // cells inside a corner's disk are skipped).
  std::vector<StepCertificate> corner_parts(sectors.size());
  parallel_for(static_cast<Index>(sectors.size()), 1, [&](Index first, Index last) {
    PolarWorkspace ws;
    for (Index i = first; i < last; ++i) {
      StepCertificate& part = corner_parts[static_cast<std::size_t>(i)];
      part.lower_bound = std::numeric_limits<Real>::infinity();
      certify_sector(s, sectors[static_cast<std::size_t>(i)], tight_enough, stops_at, o.min_cell_fraction,
                     part, ws, count_cell, [&](const Point<2>& x, Real size, const I& det) {
                       refuse(s, step, x.x(), x.y(), size, det);
                     });
    }
  });
  std::vector<StepCertificate> parts(kRoots * kRoots);
  parallel_for(kRoots * kRoots, 1, [&](Index first, Index last) {
    Workspace ws;
    std::vector<Cell> stack;
    for (Index root = first; root < last; ++root) {
      StepCertificate& part = parts[static_cast<std::size_t>(root)];
      part.lower_bound = std::numeric_limits<Real>::infinity();
      const Real h0 = side / kRoots;
      stack.assign(1, Cell{lo.x() + static_cast<Real>(root % kRoots) * h0,
                           lo.y() + static_cast<Real>(root / kRoots) * h0, h0});
      while (!stack.empty()) {
        const Cell cell = stack.back();
        stack.pop_back();
        const Real x1 = cell.x0 + cell.h, y1 = cell.y0 + cell.h;
        if (classify(P, edges, cell.x0, x1, cell.y0, y1) == CellSide::outside) continue;
        bool in_disk = false;
        for (Index i = 0; i < P.size() && !in_disk; ++i)
          in_disk =
              box_in_disk(P.vertex(i), sectors[static_cast<std::size_t>(i)].radius, cell.x0, x1, cell.y0, y1);
        if (in_disk) {
          ++part.skipped_in_corners;
          continue;
        }
        // A positive interval whose lower end is far below the sampled
        // minimum is split further while cells are not tiny, so that b_k is
        // close to the true minimum, not just above zero.
        const bool may_tighten = cell.h / 2 >= 16 * min_size;
        I det;
        {
          CGAL::Protect_FPU_rounding<true> guard;
          det = det_enclosure(s, cell.x0, x1, cell.y0, y1, stops_at, /*last_try=*/cell.h / 2 < min_size, ws);
        }
        ++part.cells;
        count_cell();
        const bool loose = det.inf() < tight_enough && may_tighten;
        if (det.inf() > 0 && !loose) {
          if (det.inf() < part.lower_bound) {
            part.lower_bound = det.inf();
            part.lower_bound_at = Point<2>(cell.x0 + cell.h / 2, cell.y0 + cell.h / 2);
          }
          continue;
        }
        if (cell.h / 2 >= min_size) {
          const Real h = cell.h / 2;
          for (int q = 0; q < 4; ++q) stack.push_back({cell.x0 + (q % 2) * h, cell.y0 + (q / 2) * h, h});
          continue;
        }
        refuse(s, step, cell.x0 + cell.h / 2, cell.y0 + cell.h / 2, cell.h, det);
      }
    }
  });
  for (const StepCertificate& part : corner_parts) c.corner_cells += part.cells;
  parts.insert(parts.end(), corner_parts.begin(), corner_parts.end());
  for (const StepCertificate& part : parts) {
    c.cells += part.cells;
    c.skipped_in_corners += part.skipped_in_corners;
    if (part.lower_bound < c.lower_bound) {
      c.lower_bound = part.lower_bound;
      c.lower_bound_at = part.lower_bound_at;
    }
  }
  if (!std::isfinite(c.lower_bound))
    throw Error("certificate: step " + std::to_string(step) + " has no cell");
  return c;
}

/// u_i = target_i − source_i, by coordinate.
std::pair<std::vector<Real>, std::vector<Real>> displacements(const Polygon& source,
                                                              const std::vector<Point<2>>& target) {
  std::vector<Real> ux, uy;
  for (Index i = 0; i < source.size(); ++i) {
    ux.push_back(target[static_cast<std::size_t>(i)].x() - source.vertex(i).x());
    uy.push_back(target[static_cast<std::size_t>(i)].y() - source.vertex(i).y());
  }
  return {ux, uy};
}

}  // namespace

std::string MapCertificate::summary() const {
  std::ostringstream os;
  os << std::setprecision(4) << "det J_f >= " << lower_bound << " certified on all of Ω0 but its vertices ("
     << steps.size() << " step" << (steps.size() == 1 ? "" : "s") << ", " << cells << " cells, "
     << corner_cells << " of them polar cells at the corners, " << format_seconds(seconds) << ")";
  return os.str();
}

std::pair<Real, Real> det_jacobian_enclosure(const Polygon& source, const std::vector<Point<2>>& target,
                                             const Point<2>& lo, const Point<2>& hi) {
  const auto [ux, uy] = displacements(source, target);
  Workspace ws;
  CGAL::Protect_FPU_rounding<true> guard;
  const I det = det_enclosure({source, ux, uy}, lo.x(), hi.x(), lo.y(), hi.y(),
                              std::numeric_limits<Real>::infinity(), /*last_try=*/true, ws);
  return {det.inf(), det.sup()};
}

std::pair<Real, Real> corner_det_jacobian_enclosure(const Polygon& source,
                                                    const std::vector<Point<2>>& target, Index vertex,
                                                    Real rho0, Real rho1, Real theta0, Real theta1) {
  const auto [ux, uy] = displacements(source, target);
  PolarWorkspace ws;
  CGAL::Protect_FPU_rounding<true> guard;
  const I det = polar_det_enclosure({source, ux, uy}, vertex, rho0, rho1, theta0, theta1,
                                    std::numeric_limits<Real>::infinity(), /*last_try=*/true, ws);
  return {det.inf(), det.sup()};
}

StepCertificate certify_mean_value_step(const Polygon& source, const std::vector<Point<2>>& target,
                                        const CertifyOptions& options, Index step) {
  require_same_vertex_count(source, Polygon(target));
  const auto [ux, uy] = displacements(source, target);
  return certify_step({source, ux, uy}, options, step);
}

MapCertificate certify_composite(const CompositeMeanValueMap& map, const CertifyOptions& options) {
  if (map.coordinates() != Coordinates::mean_value)
    throw Error(
        "the certificate covers mean value coordinates only, this map uses " + to_string(map.coordinates()),
        {.file = "", .key_path = "map.certify", .hint = "remove \"certify\" (sampled check only)"});
  Stopwatch watch;
  MapCertificate c;
  c.lower_bound = 1;
  for (Index k = 0; k < map.steps(); ++k) {
    const Polygon& P = map.polygons()[static_cast<std::size_t>(k)];
    const std::vector<Point<2>>& next = map.polygons()[static_cast<std::size_t>(k + 1)].vertices();
    c.steps.push_back(certify_mean_value_step(P, next, options, k));
    c.lower_bound *= c.steps.back().lower_bound;
    c.cells += c.steps.back().cells;
    c.corner_cells += c.steps.back().corner_cells;
  }
  c.seconds = watch.seconds();
  return c;
}

bool is_certifiable(const Map<2>& map) {
  if (const auto* m = dynamic_cast<const CompositeMeanValueMap*>(&map))
    return m->coordinates() == Coordinates::mean_value;
  if (const auto* m = dynamic_cast<const BarycentricMap*>(&map))
    return m->step().coordinates() == Coordinates::mean_value;
  return false;
}

MapCertificate certify_map(const Map<2>& map, const CertifyOptions& options) {
  if (const auto* m = dynamic_cast<const CompositeMeanValueMap*>(&map)) return certify_composite(*m, options);
  const auto* b = dynamic_cast<const BarycentricMap*>(&map);
  if (!b || b->step().coordinates() != Coordinates::mean_value)
    throw Error("no certificate for " + map.describe() + ": only mean value maps are certified",
                {.file = "", .key_path = "map.certify", .hint = "remove \"certify\" (sampled check only)"});
  Stopwatch watch;
  std::vector<Point<2>> v;
  for (std::size_t i = 0; i < b->step().source().x.size(); ++i)
    v.emplace_back(b->step().source().x[i], b->step().source().y[i]);
  const Polygon P(v, "source");
  MapCertificate c;
  c.steps.push_back(certify_step({P, b->step().displacement_x(), b->step().displacement_y()}, options, 0));
  c.lower_bound = c.steps.back().lower_bound;
  c.cells = c.steps.back().cells;
  c.corner_cells = c.steps.back().corner_cells;
  c.seconds = watch.seconds();
  return c;
}

}  // namespace warpfem::mapping
