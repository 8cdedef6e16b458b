#include "mapping/wachspress_coordinates.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "mapping/detail/nudge_inside.hpp"

namespace warpfem::mapping {

void require_convex_for(const Polygon& polygon, Coordinates type) {
  if (type == Coordinates::mean_value) return;
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const Index n = polygon.size();
  for (Index i = 0; i < n; ++i) {
    const Point<2>& a = polygon.vertex(i - 1);
    const Point<2>& b = polygon.vertex(i);
    const Point<2>& c = polygon.vertex(i + 1);
    const auto o =
        CGAL::orientation(K::Point_2(a.x(), a.y()), K::Point_2(b.x(), b.y()), K::Point_2(c.x(), c.y()));
    const bool reflex = o == CGAL::RIGHT_TURN;
    const bool flat = o == CGAL::COLLINEAR && type == Coordinates::wachspress;
    if (!reflex && !flat) continue;
    std::ostringstream os;
    os << to_string(type) << " coordinates need a " << (flat ? "strictly " : "") << "convex polygon, but "
       << polygon.name() << " has a " << (reflex ? "reflex" : "collinear") << " vertex " << i << " at ("
       << b.x() << ", " << b.y() << ")";
    throw Error(os.str(),
                {.file = "", .key_path = "", .hint = "use mean_value coordinates for non-convex polygons"});
  }
}

namespace {

/// The three-point formula at a point that is not a vertex.
void off_vertex_coordinates(Coordinates type, const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx,
                            Real* dy, std::vector<Real>& work);

}  // namespace

void three_point_coordinates_at(Coordinates type, const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx,
                                Real* dy, std::vector<Real>& work) {
  const Index n = P.size();
  Index j = 0;
  Real rj = std::numeric_limits<Real>::infinity();
  for (Index k = 0; k < n; ++k) {
    const Real r = std::hypot(P.x[k] - x, P.y[k] - y);
    if (r < rj) j = k, rj = r;
  }
  if (rj <= 1e-13 * P.scale) {  // at a vertex: Kronecker delta
    if (dx) {                   // one-sided gradient from just inside
      const Point<2> q = detail::nudge_inside(P, j);
      off_vertex_coordinates(type, P, q.x(), q.y(), phi, dx, dy, work);
    }
    std::fill(phi, phi + n, Real{0});
    phi[j] = 1;
    return;
  }
  off_vertex_coordinates(type, P, x, y, phi, dx, dy, work);
}

namespace {

void off_vertex_coordinates(Coordinates type, const PolygonArrays& P, Real x, Real y, Real* phi, Real* dx,
                            Real* dy, std::vector<Real>& work) {
  const Index n = P.size();
  const bool grad = dx != nullptr;
  const bool harmonic = type == Coordinates::discrete_harmonic;
  work.resize(static_cast<std::size_t>(8 * n));
  Real* sx = work.data();
  Real* sy = sx + n;
  Real* r2 = sy + n;
  Real* A = r2 + n;
  Real* w = A + n;
  Real* gw = w + n;  // 2n
  auto nx = [n](Index k) { return k + 1 == n ? Index{0} : k + 1; };
  auto pv = [n](Index k) { return k == 0 ? n - 1 : k - 1; };

  for (Index k = 0; k < n; ++k) {
    sx[k] = P.x[k] - x;
    sy[k] = P.y[k] - y;
    r2[k] = sx[k] * sx[k] + sy[k] * sy[k];
  }
  // A_k and the edge k* nearest (in distance to its line) to x.
  Index ks = 0;
  Real best = 0;
  for (Index k = 0; k < n; ++k) {
    const Index kn = nx(k);
    A[k] = 0.5 * (sx[k] * sy[kn] - sy[k] * sx[kn]);
    const Real len = std::hypot(P.x[kn] - P.x[k], P.y[kn] - P.y[k]);
    const Real dist = std::abs(A[k]) / len;
    if (k == 0 || dist < best) {
      best = dist;
      ks = k;
    }
  }
  auto gA = [&](Index k, Real& gx, Real& gy) {  // ∇A_k
    const Index kn = nx(k);
    gx = 0.5 * (P.y[k] - P.y[kn]);
    gy = 0.5 * (P.x[kn] - P.x[k]);
  };
  const Real sigma = A[ks];
  Real gsx, gsy;
  gA(ks, gsx, gsy);
  for (Index k = 0; k < n; ++k) {
    const Index kp = pv(k), kn = nx(k);
    // numerator N_k and ∇N_k
    Real N, gNx = 0, gNy = 0;
    if (!harmonic) {
      N = 0.5 * ((P.x[kn] - P.x[k]) * (P.y[kp] - P.y[k]) - (P.y[kn] - P.y[k]) * (P.x[kp] - P.x[k]));
    } else {
      const Real B = 0.5 * (sx[kp] * sy[kn] - sy[kp] * sx[kn]);
      N = r2[kn] * A[kp] - r2[k] * B + r2[kp] * A[k];
      if (grad) {
        Real ax, ay, bx, by;
        gA(kp, ax, ay);
        gA(k, bx, by);
        const Real gBx = 0.5 * (P.y[kp] - P.y[kn]), gBy = 0.5 * (P.x[kn] - P.x[kp]);
        gNx =
            -2 * sx[kn] * A[kp] + r2[kn] * ax + 2 * sx[k] * B - r2[k] * gBx - 2 * sx[kp] * A[k] + r2[kp] * bx;
        gNy =
            -2 * sy[kn] * A[kp] + r2[kn] * ay + 2 * sy[k] * B - r2[k] * gBy - 2 * sy[kp] * A[k] + r2[kp] * by;
      }
    }
    Real ax, ay, bx, by;
    gA(kp, ax, ay);
    gA(k, bx, by);
    if (k == ks) {  // σ cancels A_k: w̃ = N / A_{k−1}
      w[k] = N / A[kp];
      gw[k] = (gNx - w[k] * ax) / A[kp];
      gw[n + k] = (gNy - w[k] * ay) / A[kp];
    } else if (kp == ks) {  // σ cancels A_{k−1}: w̃ = N / A_k
      w[k] = N / A[k];
      gw[k] = (gNx - w[k] * bx) / A[k];
      gw[n + k] = (gNy - w[k] * by) / A[k];
    } else {
      const Real D = A[kp] * A[k];
      const Real wk = N / D;
      w[k] = sigma * wk;
      if (grad) {
        const Real gwx = (gNx - wk * (ax * A[k] + A[kp] * bx)) / D;
        const Real gwy = (gNy - wk * (ay * A[k] + A[kp] * by)) / D;
        gw[k] = sigma * gwx + wk * gsx;
        gw[n + k] = sigma * gwy + wk * gsy;
      }
    }
  }
  // Normalize (weights of convex polygons do not need the dominant-weight treatment).
  Real W = 0, Wx = 0, Wy = 0;
  for (Index k = 0; k < n; ++k) {
    W += w[k];
    if (grad) {
      Wx += gw[k];
      Wy += gw[n + k];
    }
  }
  for (Index k = 0; k < n; ++k) {
    phi[k] = w[k] / W;
    if (grad) {
      dx[k] = (gw[k] - phi[k] * Wx) / W;
      dy[k] = (gw[n + k] - phi[k] * Wy) / W;
    }
  }
}

}  // namespace

void three_point_coordinates(Coordinates type, const PolygonArrays& P, const Points<2>& x, MatrixX& phi,
                             MatrixX* dphi_dx, MatrixX* dphi_dy) {
  const Index N = x.rows(), n = P.size();
  phi.resize(N, n);
  if (dphi_dx) {
    dphi_dx->resize(N, n);
    dphi_dy->resize(N, n);
  }
  std::vector<Real> work, buf(static_cast<std::size_t>(3 * n));
  for (Index p = 0; p < N; ++p) {
    three_point_coordinates_at(type, P, x(p, 0), x(p, 1), buf.data(), dphi_dx ? buf.data() + n : nullptr,
                               buf.data() + 2 * n, work);
    for (Index i = 0; i < n; ++i) {
      phi(p, i) = buf[i];
      if (dphi_dx) {
        (*dphi_dx)(p, i) = buf[n + i];
        (*dphi_dy)(p, i) = buf[2 * n + i];
      }
    }
  }
}

}  // namespace warpfem::mapping
