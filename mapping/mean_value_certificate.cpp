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
    if (D.v.sup() < 0) {  // the edge is seen under more than 90°: t = (P − D) / A
      // Unless A is well away from 0 (relative to its width), the box is at
      // or close to the segment: then (P − D) times A, through the scale.
      const Real lo = std::min(std::abs(A.v.inf()), std::abs(A.v.sup()));
      const Real hi = std::max(std::abs(A.v.inf()), std::abs(A.v.sup()));
      const J PmD = P - D;
      if ((A.v.inf() > 0 || A.v.sup() < 0) && lo > kNearRatio * hi && PmD.v.inf() < kNearTan * hi) {
        t[k] = PmD / A;
      } else {
        near[static_cast<std::size_t>(k)] = 1;
        t[k] = PmD;
        scale = scale * A;
      }
    } else {
      t[k] = A / (P + D);
    }
  }
  for (Index k = 0; k < n; ++k) {
    if (!near[static_cast<std::size_t>(k)]) {
      t[k] = t[k] * scale;
      continue;
    }
    for (Index e = 0; e < n; ++e)  // Π over the other near edges
      if (e != k && near[static_cast<std::size_t>(e)]) t[k] = t[k] * area[e];
  }
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

/// The least det J_k at the points of a grid × grid lattice over P_k's
/// bounding box that lie inside P_k and outside the ρ-disks (+∞ if none):
/// an upper bound of the minimum the certificate bounds from below.
Real sampled_min_det(const StepData& s, Real rho, int grid) {
  const Polygon& P = s.polygon;
  const Point<2> lo = P.bbox_min(), hi = P.bbox_max();
  std::vector<Point<2>> inside;
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const Point<2> x(lo.x() + (hi.x() - lo.x()) * (i + 0.5) / grid,
                       lo.y() + (hi.y() - lo.y()) * (j + 0.5) / grid);
      bool in_disk = false;
      for (Index v = 0; v < P.size() && !in_disk; ++v) in_disk = (x - P.vertex(v)).norm() <= rho;
      if (!in_disk && P.side_of(x) > 0) inside.push_back(x);
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

StepCertificate certify_step(const StepData& s, const CertifyOptions& o, Index step) {
  const Polygon& P = s.polygon;
  const Point<2> lo = P.bbox_min(), hi = P.bbox_max();
  const Real diam = (hi - lo).norm();
  StepCertificate c;
  c.rho = o.rho_fraction * diam;
  // Cells whose lower end is already above tightness × the sampled minimum
  // do not decide b_k: they stop at their first positive interval. (A
  // sampled minimum ≤ 0 means the step folds; the quadtree then finds where.)
  const Real sampled = o.tightness > 0 ? sampled_min_det(s, c.rho, o.sample_grid) : 0;
  const Real tight_enough = std::isfinite(sampled) ? o.tightness * std::max(sampled, Real{0}) : 0;
  c.lower_bound = std::numeric_limits<Real>::infinity();
  const Real min_size = o.min_cell_fraction * c.rho;
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
  std::vector<StepCertificate> parts(kRoots * kRoots);
  std::atomic<Index> total_cells{0};
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
          in_disk = box_in_disk(P.vertex(i), c.rho, cell.x0, x1, cell.y0, y1);
        if (in_disk) {
          ++part.skipped_in_disks;
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
        if (++total_cells > o.max_cells)
          throw Error(
              "certificate: step " + std::to_string(step) + " needs more than " +
                  std::to_string(o.max_cells) + " quadtree cells",
              {.file = "",
               .key_path = "map.certify",
               .hint = "use a finer partition (more steps), or \"certify\": false (sampled check only)"});
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
  for (const StepCertificate& part : parts) {
    c.cells += part.cells;
    c.skipped_in_disks += part.skipped_in_disks;
    if (part.lower_bound < c.lower_bound) {
      c.lower_bound = part.lower_bound;
      c.lower_bound_at = part.lower_bound_at;
    }
  }
  if (!std::isfinite(c.lower_bound))
    throw Error("certificate: step " + std::to_string(step) + " has no cell outside the vertex disks");
  return c;
}

/// min det J_f over points of Ω0 inside the ρ-disks (polar rings, interior points only).
void sample_disks(const Map<2>& f, const Polygon& source, Real rho, int per_vertex, MapCertificate& out) {
  const int rings = 6, rays = std::max(1, per_vertex / rings);
  std::vector<Point<2>> pts;
  for (Index i = 0; i < source.size(); ++i)
    for (int a = 0; a < rays; ++a)
      for (int k = 1; k <= rings; ++k) {
        const Real ang = 2 * std::numbers::pi * (a + 0.5) / rays;
        const Real rad = rho * std::pow(10.0, -3.0 * (rings - k) / (rings - 1));  // ρ·1e-3 … ρ
        const Point<2> p = source.vertex(i) + rad * Point<2>(std::cos(ang), std::sin(ang));
        if (source.side_of(p) > 0) pts.push_back(p);
      }
  out.disk_samples = static_cast<Index>(pts.size());
  out.sampled_min_in_disks = std::numeric_limits<Real>::quiet_NaN();
  if (pts.empty()) return;
  Points<2> x(static_cast<Index>(pts.size()), 2);
  for (Index p = 0; p < x.rows(); ++p) x.row(p) = pts[static_cast<std::size_t>(p)].transpose();
  Jacobians<2> J;
  f.jacobian(x, J);
  Real m = std::numeric_limits<Real>::infinity();
  for (Index p = 0; p < x.rows(); ++p) m = std::min(m, J(p, 0) * J(p, 3) - J(p, 1) * J(p, 2));
  out.sampled_min_in_disks = m;
}

}  // namespace

std::string MapCertificate::summary() const {
  std::ostringstream os;
  os << std::setprecision(4) << "det J_f >= " << lower_bound << " certified on Ω0 outside disks of radius "
     << rho << " around the vertices (" << steps.size() << " step" << (steps.size() == 1 ? "" : "s") << ", "
     << cells << " cells, " << format_seconds(seconds) << "); sampled min det J_f inside the disks "
     << sampled_min_in_disks << " (" << disk_samples << " samples, not certified)";
  return os.str();
}

std::pair<Real, Real> det_jacobian_enclosure(const Polygon& source, const std::vector<Point<2>>& target,
                                             const Point<2>& lo, const Point<2>& hi) {
  std::vector<Real> ux, uy;
  for (Index i = 0; i < source.size(); ++i) {
    ux.push_back(target[static_cast<std::size_t>(i)].x() - source.vertex(i).x());
    uy.push_back(target[static_cast<std::size_t>(i)].y() - source.vertex(i).y());
  }
  Workspace ws;
  CGAL::Protect_FPU_rounding<true> guard;
  const I det = det_enclosure({source, ux, uy}, lo.x(), hi.x(), lo.y(), hi.y(),
                              std::numeric_limits<Real>::infinity(), /*last_try=*/true, ws);
  return {det.inf(), det.sup()};
}

StepCertificate certify_mean_value_step(const Polygon& source, const std::vector<Point<2>>& target,
                                        const CertifyOptions& options, Index step) {
  require_same_vertex_count(source, Polygon(target));
  std::vector<Real> ux, uy;
  for (Index i = 0; i < source.size(); ++i) {
    ux.push_back(target[static_cast<std::size_t>(i)].x() - source.vertex(i).x());
    uy.push_back(target[static_cast<std::size_t>(i)].y() - source.vertex(i).y());
  }
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
  }
  c.rho = c.steps.front().rho;
  sample_disks(map, map.polygons().front(), c.rho, options.disk_samples_per_vertex, c);
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
  c.rho = c.steps.back().rho;
  sample_disks(map, P, c.rho, options.disk_samples_per_vertex, c);
  c.seconds = watch.seconds();
  return c;
}

}  // namespace warpfem::mapping
