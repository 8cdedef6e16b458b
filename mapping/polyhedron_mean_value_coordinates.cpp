#include "mapping/polyhedron_mean_value_coordinates.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "mapping/detail/polyhedron_mean_value_kernel.hpp"

namespace warpfem::mapping {

PolyhedronArrays::PolyhedronArrays(const Polyhedron& polyhedron)
    : PolyhedronArrays(polyhedron.vertices(), polyhedron.triangles()) {}

PolyhedronArrays::PolyhedronArrays(const std::vector<Point<3>>& vertices,
                                   const std::vector<Polyhedron::Triangle>& triangles) {
  Point<3> lo = vertices.front(), hi = vertices.front();
  for (const auto& v : vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  center = 0.5 * (lo + hi);
  scale = (hi - lo).norm();
  for (const auto& v : vertices) {
    x.push_back((v.x() - center.x()) / scale);
    y.push_back((v.y() - center.y()) / scale);
    z.push_back((v.z() - center.z()) / scale);
  }
  std::map<std::pair<int, int>, int> edge_index;
  const auto edge = [&](int u, int v) {
    const auto key = std::minmax(u, v);
    const auto [it, inserted] = edge_index.try_emplace(key, static_cast<int>(edge_a.size()));
    if (inserted) edge_a.push_back(key.first), edge_b.push_back(key.second);
    return it->second;
  };
  for (const auto& t : triangles) {
    const int u = static_cast<int>(t[0]), v = static_cast<int>(t[1]), w = static_cast<int>(t[2]);
    a.push_back(u);
    b.push_back(v);
    c.push_back(w);
    const Point<3> pu(x[u], y[u], z[u]), pv(x[v], y[v], z[v]), pw(x[w], y[w], z[w]);
    two_area.push_back((pv - pu).cross(pw - pu).norm());
    triangle_edges.push_back(edge(v, w));
    triangle_edges.push_back(edge(w, u));
    triangle_edges.push_back(edge(u, v));
  }
  schedule_edges();
}

void PolyhedronArrays::schedule_edges() {
  const int m = static_cast<int>(a.size()), ne = static_cast<int>(edge_a.size());
  std::vector<std::vector<int>> edge_triangles(static_cast<std::size_t>(ne));
  for (int t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k)
      edge_triangles[static_cast<std::size_t>(triangle_edges[3 * t + k])].push_back(t);
  // Breadth first over triangles sharing an edge: the open edges are the
  // boundary of the visited region.
  order.clear();
  std::vector<char> seen(static_cast<std::size_t>(m), 0);
  for (int root = 0; root < m; ++root) {
    if (seen[static_cast<std::size_t>(root)]) continue;
    seen[static_cast<std::size_t>(root)] = 1;
    for (std::size_t head = order.size(), tail = (order.push_back(root), head); tail < order.size(); ++tail)
      for (int k = 0; k < 3; ++k)
        for (const int u : edge_triangles[static_cast<std::size_t>(triangle_edges[3 * order[tail] + k])])
          if (!seen[static_cast<std::size_t>(u)]) seen[static_cast<std::size_t>(u)] = 1, order.push_back(u);
  }
  // Each edge is computed kLookahead triangles before the first one that uses
  // it, so that the latency of its square root and division can overlap the
  // triangles in between.
  constexpr int kLookahead = 2;
  edge_first.assign(1, 0);
  scheduled_edges.clear();
  edge_slot.assign(static_cast<std::size_t>(ne), -1);
  std::vector<int> uses_left(static_cast<std::size_t>(ne)), free_slots;
  for (int e = 0; e < ne; ++e)
    uses_left[static_cast<std::size_t>(e)] =
        static_cast<int>(edge_triangles[static_cast<std::size_t>(e)].size());
  slot_count = 0;
  const auto schedule = [&](int t) {
    for (int k = 0; k < 3; ++k) {
      const int e = triangle_edges[3 * t + k];
      if (edge_slot[static_cast<std::size_t>(e)] >= 0) continue;  // computed for an earlier triangle
      if (free_slots.empty()) free_slots.push_back(slot_count++);
      edge_slot[static_cast<std::size_t>(e)] = free_slots.back();
      free_slots.pop_back();
      scheduled_edges.push_back(e);
    }
  };
  for (int i = 0; i < m; ++i) {
    if (i == 0)
      for (int j = 0; j <= kLookahead && j < m; ++j) schedule(order[static_cast<std::size_t>(j)]);
    else if (i + kLookahead < m)
      schedule(order[static_cast<std::size_t>(i + kLookahead)]);
    edge_first.push_back(static_cast<int>(scheduled_edges.size()));
    const int t = order[static_cast<std::size_t>(i)];
    for (int k = 0; k < 3; ++k) {
      const int e = triangle_edges[3 * t + k];
      if (--uses_left[static_cast<std::size_t>(e)] == 0)
        free_slots.push_back(edge_slot[static_cast<std::size_t>(e)]);
    }
  }
}

namespace {

/// Below this distance, relative to the shortest edge at a vertex (or to the
/// edge's length), a point is on that vertex (edge).
constexpr Real kSnap = 1e-13;
/// A triangle whose plane passes within this fraction of the nearest of its
/// vertices from x, with x's projection outside it, uses the h-factored form.
constexpr Real kFactoredPlane = 0.25;

/// Forward-mode derivative: a value and its gradient with respect to x.
struct Dual {
  double v = 0, d[3] = {0, 0, 0};
  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT: constants promote implicitly
};
inline Dual operator+(const Dual& a, const Dual& b) {
  Dual r(a.v + b.v);
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] + b.d[k];
  return r;
}
inline Dual operator-(const Dual& a, const Dual& b) {
  Dual r(a.v - b.v);
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] - b.d[k];
  return r;
}
inline Dual operator-(const Dual& a) {
  Dual r(-a.v);
  for (int k = 0; k < 3; ++k) r.d[k] = -a.d[k];
  return r;
}
inline Dual operator*(const Dual& a, const Dual& b) {
  Dual r(a.v * b.v);
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
  return r;
}
inline Dual operator/(const Dual& a, const Dual& b) {
  const double ib = 1 / b.v;
  Dual r(a.v * ib);
  for (int k = 0; k < 3; ++k) r.d[k] = (a.d[k] - r.v * b.d[k]) * ib;
  return r;
}
inline Dual& operator+=(Dual& a, const Dual& b) {
  return a = a + b;
}
/// Applies f with f(a.v) = value and f'(a.v) = slope.
inline Dual chain(const Dual& a, double value, double slope) {
  Dual r(value);
  for (int k = 0; k < 3; ++k) r.d[k] = slope * a.d[k];
  return r;
}
inline Dual sqrt(const Dual& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, 0.5 / s);
}
inline Dual abs(const Dual& a) {
  return a.v < 0 ? -a : a;
}
inline Dual atan(const Dual& a) {
  return chain(a, std::atan(a.v), 1 / (1 + a.v * a.v));
}
/// atan(z) / z, also for z → 0.
inline Dual atanc(const Dual& z) {
  if (std::abs(z.v) > 1e-3) return atan(z) / z;
  const Dual z2 = z * z;
  return 1.0 - z2 * (1.0 / 3 - z2 * (1.0 / 5 - z2 * (1.0 / 7)));
}

struct DVec {
  Dual x, y, z;
};
inline Dual dot(const DVec& a, const DVec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Dual dot(const DVec& a, const Point<3>& b) {
  return a.x * b.x() + a.y * b.y() + a.z * b.z();
}
inline DVec cross(const DVec& a, const DVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

Point<3> vertex(const PolyhedronArrays& P, Index v) {
  return {P.x[v], P.y[v], P.z[v]};
}

/// Normalizes scaled weights w̃ (with gradients) into φ, ∇φ. The dominant
/// weight d is treated apart, ∇φ_d = (S ∇w̃_d − w̃_d ∇S) / W², S = Σ_{k≠d} w̃_k,
/// avoiding the cancellation of (1 − φ_d) ∇w̃_d next to a vertex.
void normalize(const std::vector<Dual>& w, Real* phi, Real* dx, Real* dy, Real* dz) {
  const Index n = static_cast<Index>(w.size());
  Index d = 0;
  for (Index k = 1; k < n; ++k)
    if (std::abs(w[k].v) > std::abs(w[d].v)) d = k;
  Dual S;
  for (Index k = 0; k < n; ++k)
    if (k != d) S += w[k];
  const Dual W = S + w[d];
  for (Index k = 0; k < n; ++k) phi[k] = w[k].v / W.v;
  if (!dx) return;
  Real* g[3] = {dx, dy, dz};
  for (Index k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) g[c][k] = (w[k].d[c] - phi[k] * W.d[c]) / W.v;
  for (int c = 0; c < 3; ++c) g[c][d] = (S.v * w[d].d[c] - w[d].v * S.d[c]) / (W.v * W.v);
}

/// A triangle seen from x: its vertices, unit normal ν, 2A = |M|, the signed
/// distance h of x below its plane (h > 0 inside), and whether x projects into it.
struct Face {
  int v[3];
  Point<3> nu;
  Real two_area;
  Dual h;
  bool over;
};

/// Face t seen from x, with s0 = p_{v[0]} − x.
Face make_face(const PolyhedronArrays& P, Index t, const DVec& s0, const Point<3>& x) {
  Face f;
  f.v[0] = P.a[t], f.v[1] = P.b[t], f.v[2] = P.c[t];
  const Point<3> p0 = vertex(P, f.v[0]), p1 = vertex(P, f.v[1]), p2 = vertex(P, f.v[2]);
  const Point<3> M = (p1 - p0).cross(p2 - p0);
  f.two_area = M.norm();
  f.nu = M / f.two_area;
  f.h = dot(s0, f.nu);
  f.over = true;
  for (int e = 0; e < 3; ++e) {
    const Point<3> a = vertex(P, f.v[(e + 1) % 3]) - x, b = vertex(P, f.v[(e + 2) % 3]) - x;
    if (f.nu.dot(a.cross(b)) < 0) f.over = false;
  }
  return f;
}

/// The contribution of face f to the weights of its vertices, scaled by eta
/// (s[i] = p_{v[i]} − x, r[i] = |s[i]|). `eta_face`: f is the face x is
/// nearest to, with eta = sigma h.
void face_weights(const PolyhedronArrays& P, const Face& f, const DVec* s, const Dual* r, const Dual& eta,
                  bool eta_face, double sigma, Dual* w) {
  // Edge e is opposite vertex e: (a, b) = (v[e+1], v[e+2]), N_e = s_a × s_b.
  DVec N[3];
  Dual L[3], k[3];  // k_e = β_e / L_e
  Real rho = std::numeric_limits<Real>::infinity();
  for (int e = 0; e < 3; ++e) {
    const int a = (e + 1) % 3, b = (e + 2) % 3;
    N[e] = cross(s[a], s[b]);
    L[e] = sqrt(dot(N[e], N[e]));
    const Dual c = dot(s[a], s[b]);
    const Dual den = r[a] * r[b] + abs(c);
    const Dual z = L[e] / den;  // tan(β/2) if c >= 0, cot(β/2) otherwise
    k[e] = c.v >= 0 ? 2.0 * atanc(z) / den : (std::numbers::pi - 2.0 * atan(z)) / L[e];
    rho = std::min(rho, r[e].v);
  }
  if (!f.over && std::abs(f.h.v) < kFactoredPlane * rho) {
    // x near the plane, projecting outside: w_i = h (c_i G + P_i) / (2|M|) with
    // c_e = ν·N_e, g_e = ν × (p_b − p_a), P_i = Σ_e k_e g_e·g_i and
    // G = Q / h², Q = Σ_e β_e c_e / L_e, whose O(1) part (the winding angle
    // of the projected triangle) is exactly 0 outside; what remains is written
    // with the h² factored out of every term.
    const Dual h = f.h, h2 = h * h;
    Point<3> g[3];
    Dual c[3];
    DVec A[3];
    for (int e = 0; e < 3; ++e) {
      const Index a = f.v[(e + 1) % 3], b = f.v[(e + 2) % 3];
      g[e] = f.nu.cross(vertex(P, b) - vertex(P, a));
      c[e] = dot(N[e], f.nu);
      A[e] = {s[e].x - h * f.nu.x(), s[e].y - h * f.nu.y(), s[e].z - h * f.nu.z()};
    }
    Dual G;
    for (int e = 0; e < 3; ++e) {
      if (c[e].v == 0) continue;  // x on this edge's line in the plane: the term vanishes
      const int a = (e + 1) % 3, b = (e + 2) % 3;
      const Dual aa = dot(A[a], A[b]);  // projected s_a · s_b
      const Dual ss = aa + h2;          // s_a · s_b
      const Dual ac = abs(c[e]);
      const Real g2 = g[e].squaredNorm();
      const Dual X = aa * g2 / (L[e] + ac) - ac;  // (β − β⁰) = atan(h² X / Y)
      const Dual Y = ss * aa + L[e] * ac;
      const Dual dbeta = X / Y * atanc(h2 * X / Y);
      const Dual qq = h2 * g2 / (c[e] * c[e]);
      const Dual sq = sqrt(1.0 + qq);
      const Dual delta = g2 / (c[e] * c[e]) / (sq * (sq + 1.0));  // (1 − c/L) / h²
      const Dual term = dbeta - k[e] * L[e] * delta;
      G += c[e].v > 0 ? term : -term;
    }
    for (int i = 0; i < 3; ++i) {
      Dual Pi;
      for (int e = 0; e < 3; ++e) Pi += k[e] * g[e].dot(g[i]);
      w[i] = eta * h * (c[i] * G + Pi) / (2 * f.two_area);
    }
    return;
  }
  // Direct form: w_i = m · N_i / D, m = ½ Σ k_e N_e, D = h |M|.
  DVec mv{Dual(), Dual(), Dual()};
  for (int e = 0; e < 3; ++e) {
    const Dual ke = 0.5 * k[e];
    mv.x += ke * N[e].x;
    mv.y += ke * N[e].y;
    mv.z += ke * N[e].z;
  }
  const Dual factor = eta_face ? Dual(sigma / f.two_area) : eta / (f.h * f.two_area);
  for (int i = 0; i < 3; ++i) w[i] = factor * dot(mv, N[i]);
}

/// x as a dual number (derivatives with respect to x).
DVec dual_point(const Point<3>& x) {
  DVec X;
  X.x = Dual(x.x());
  X.y = Dual(x.y());
  X.z = Dual(x.z());
  X.x.d[0] = X.y.d[1] = X.z.d[2] = 1;
  return X;
}

/// The robust formula at a point (normalized coordinates) that is not on a
/// vertex or an edge; gradients with respect to normalized coordinates.
void robust_coordinates(const PolyhedronArrays& P, const Point<3>& x, Real* phi, Real* dx, Real* dy,
                        Real* dz) {
  const Index n = P.size(), m = P.triangle_count();
  const DVec X = dual_point(x);
  std::vector<DVec> s(static_cast<std::size_t>(n));
  std::vector<Dual> r(static_cast<std::size_t>(n));
  Index j = 0;
  for (Index v = 0; v < n; ++v) {
    s[v] = {P.x[v] - X.x, P.y[v] - X.y, P.z[v] - X.z};
    r[v] = sqrt(dot(s[v], s[v]));
    if (r[v].v < r[j].v) j = v;
  }
  std::vector<Face> face(static_cast<std::size_t>(m));
  Dual eta = r[j];  // weights are scaled by the distance to the surface (≤ nearest vertex)
  Index eta_face = -1;
  double sigma = 1;
  for (Index t = 0; t < m; ++t) {
    const Face& f = face[t] = make_face(P, t, s[P.a[t]], x);
    if (f.over && std::abs(f.h.v) < eta.v) {
      sigma = f.h.v < 0 ? -1 : 1;
      eta = sigma * f.h;
      eta_face = t;
    }
  }
  std::vector<Dual> w(static_cast<std::size_t>(n));
  for (Index t = 0; t < m; ++t) {
    const Face& f = face[t];
    const DVec sf[3] = {s[f.v[0]], s[f.v[1]], s[f.v[2]]};
    const Dual rf[3] = {r[f.v[0]], r[f.v[1]], r[f.v[2]]};
    Dual wf[3];
    face_weights(P, f, sf, rf, eta, t == eta_face, sigma, wf);
    for (int i = 0; i < 3; ++i) w[f.v[i]] += wf[i];
  }
  normalize(w, phi, dx, dy, dz);
}

/// The unscaled contribution (η = 1) of face t to the weights of its vertices at
/// x, for a point the batched kernel found near the plane of t and left t out
/// for; false if x projects into t (x is near the surface: the robust path).
bool near_plane_face_weights(const PolyhedronArrays& P, const Point<3>& x, Index t, Dual* w) {
  const DVec X = dual_point(x);
  const int v[3] = {P.a[t], P.b[t], P.c[t]};
  DVec s[3];
  Dual r[3];
  for (int i = 0; i < 3; ++i) {
    s[i] = {P.x[v[i]] - X.x, P.y[v[i]] - X.y, P.z[v[i]] - X.z};
    r[i] = sqrt(dot(s[i], s[i]));
  }
  const Face f = make_face(P, t, s[0], x);
  if (f.over) return false;
  face_weights(P, f, s, r, Dual(1.0), false, 1, w);
  return true;
}

/// The triangles (up to two) that contain edge (a, b), and the shortest edge at a vertex.
struct Neighbourhood {
  static Real shortest_edge_at(const PolyhedronArrays& P, Index v) {
    Real l = std::numeric_limits<Real>::infinity();
    const Point<3> p = vertex(P, v);
    for (Index t = 0; t < P.triangle_count(); ++t) {
      const int tv[3] = {P.a[t], P.b[t], P.c[t]};
      for (int e = 0; e < 3; ++e)
        if (tv[e] == v) {
          l = std::min(l, (vertex(P, tv[(e + 1) % 3]) - p).norm());
          l = std::min(l, (vertex(P, tv[(e + 2) % 3]) - p).norm());
        }
    }
    return l;
  }
  /// Σ of the unit normals of the triangles that contain all of `verts` (1 or 2 vertices).
  static Point<3> normal_sum(const PolyhedronArrays& P, Index v0, Index v1) {
    Point<3> sum = Point<3>::Zero();
    for (Index t = 0; t < P.triangle_count(); ++t) {
      const int tv[3] = {P.a[t], P.b[t], P.c[t]};
      const bool has0 = tv[0] == v0 || tv[1] == v0 || tv[2] == v0;
      const bool has1 = v1 < 0 || tv[0] == v1 || tv[1] == v1 || tv[2] == v1;
      if (!has0 || !has1) continue;
      sum += (vertex(P, tv[1]) - vertex(P, tv[0])).cross(vertex(P, tv[2]) - vertex(P, tv[0])).normalized();
    }
    return sum;
  }
};

/// A point a tiny step inside from `p` (normal sum `nsum` outward), where the
/// coordinates are differentiable; the step is far above the snap distance and
/// the rounding of the coordinates.
Point<3> nudge_inside(const Point<3>& p, const Point<3>& nsum, Real length) {
  const Real ulp_floor =
      64 * std::numeric_limits<Real>::epsilon() * std::max(Real{1}, p.cwiseAbs().maxCoeff());
  return p - std::max(1e-7 * length, ulp_floor) * nsum.normalized();
}

/// Robust evaluation in normalized coordinates (gradients too).
void coordinates_normalized(const PolyhedronArrays& P, const Point<3>& x, Real* phi, Real* dx, Real* dy,
                            Real* dz) {
  const Index n = P.size();
  Index j = 0;
  Real rj = std::numeric_limits<Real>::infinity();
  for (Index v = 0; v < n; ++v) {
    const Real r = (vertex(P, v) - x).norm();
    if (r < rj) j = v, rj = r;
  }
  const Real lj = Neighbourhood::shortest_edge_at(P, j);
  if (rj <= kSnap * lj) {  // on a vertex: Kronecker delta
    if (dx)
      robust_coordinates(P, nudge_inside(vertex(P, j), Neighbourhood::normal_sum(P, j, -1), lj), phi, dx, dy,
                         dz);
    std::fill(phi, phi + n, Real{0});
    phi[j] = 1;
    return;
  }
  // On an edge (only edges at the nearest vertex can be that close: checking all is simpler).
  for (Index t = 0; t < P.triangle_count(); ++t) {
    const int tv[3] = {P.a[t], P.b[t], P.c[t]};
    for (int e = 0; e < 3; ++e) {
      const Index a = tv[e], b = tv[(e + 1) % 3];
      if (a > b) continue;  // each edge once
      const Point<3> pa = vertex(P, a), ab = vertex(P, b) - pa;
      const Real len2 = ab.squaredNorm();
      const Real u = (x - pa).dot(ab) / len2;
      if (u <= 0 || u >= 1) continue;
      if ((x - pa - u * ab).norm() > kSnap * std::sqrt(len2)) continue;
      if (dx)
        robust_coordinates(P, nudge_inside(x, Neighbourhood::normal_sum(P, a, b), std::sqrt(len2)), phi, dx,
                           dy, dz);
      std::fill(phi, phi + n, Real{0});
      phi[a] = 1 - u;
      phi[b] = u;
      return;
    }
  }
  robust_coordinates(P, x, phi, dx, dy, dz);
}

Point<3> normalized_point(const PolyhedronArrays& P, Real x, Real y, Real z) {
  return {(x - P.center.x()) / P.scale, (y - P.center.y()) / P.scale, (z - P.center.z()) / P.scale};
}

/// A face the kernel left out because x is near its plane: its h-factored
/// contribution, unless x projects into it or is near several planes (then the
/// point is flagged for the robust path).
template <bool kGrad>
WARPFEM_KERNEL_INLINE void add_near_plane_faces(const PolyhedronArrays& P, int cnt,
                                                detail::PolyhedronScratch& s) {
  for (int p = 0; p < cnt; ++p) {
    if (s.flag[p] != 0.0 || s.plane[p] == 0.0) continue;
    const Index t = static_cast<Index>(s.plane_face[p]);
    Dual wf[3];
    if (s.plane[p] != 1.0 || !near_plane_face_weights(P, Point<3>(s.px[p], s.py[p], s.pz[p]), t, wf)) {
      s.flag[p] = 1.0;
      continue;
    }
    const int v[3] = {P.a[t], P.b[t], P.c[t]};
    for (int i = 0; i < 3; ++i) {
      s.weight_row(v[i], 0)[p] += wf[i].v;
      if constexpr (kGrad)
        for (int c = 0; c < 3; ++c) s.weight_row(v[i], 1 + c)[p] += wf[i].d[c];
    }
  }
}

/// The block of points p0 .. p0 + cnt of x, normalized, into the scratch.
WARPFEM_KERNEL_INLINE void load_block(const PolyhedronArrays& P, const Points<3>& x, Index p0, int cnt,
                                      detail::PolyhedronScratch& s) {
  const Index N = x.rows();
  const Real *X = x.data(), *Y = X + N, *Z = Y + N;
  for (int p = 0; p < cnt; ++p) {
    s.px[p] = (X[p0 + p] - P.center.x()) / P.scale;
    s.py[p] = (Y[p0 + p] - P.center.y()) / P.scale;
    s.pz[p] = (Z[p0 + p] - P.center.z()) / P.scale;
  }
}

template <bool kGrad>
WARPFEM_KERNEL_INLINE void evaluate_blocks(const PolyhedronArrays& P, const Points<3>& x, Index first,
                                           Index last, MatrixX& phi, MatrixX* dphi_dx, MatrixX* dphi_dy,
                                           MatrixX* dphi_dz) {
  constexpr int B = detail::kPolyhedronBlock;
  const Index N = x.rows(), n = P.size();
  const int m = static_cast<int>(P.triangle_count());
  const Real isc = 1 / P.scale;
  detail::PolyhedronScratch s;
  s.resize(P);
  std::vector<Real> robust(static_cast<std::size_t>(4 * n));
  alignas(64) double iW[B], iWs[B], Wx[B], Wy[B], Wz[B];
  for (Index p0 = first * B; p0 < std::min(N, last * B); p0 += B) {
    const int cnt = static_cast<int>(std::min<Index>(B, N - p0));
    load_block(P, x, p0, cnt, s);
    detail::PolyhedronPrefetch next;
    if (p0 + B < N) {
      next.base[0] = phi.data() + p0 + B;
      if constexpr (kGrad) {
        next.base[1] = dphi_dx->data() + p0 + B;
        next.base[2] = dphi_dy->data() + p0 + B;
        next.base[3] = dphi_dz->data() + p0 + B;
      }
      next.stride = static_cast<long>(N);
      next.rows = static_cast<int>(n) * (kGrad ? 4 : 1);
      next.per_step = (next.rows + m - 1) / m;
    }
    detail::polyhedron_block<kGrad>(P, cnt, s, p0 + B < N ? &next : nullptr);
    add_near_plane_faces<kGrad>(P, cnt, s);
    for (int p = 0; p < cnt; ++p) iW[p] = Wx[p] = Wy[p] = Wz[p] = 0;
    for (int v = 0; v < static_cast<int>(n); ++v) {
      const double* w = s.weight_row(v, 0);
      WARPFEM_IVDEP
      for (int p = 0; p < cnt; ++p) iW[p] += w[p];
      if constexpr (kGrad) {
        const double* gx = s.weight_row(v, 1);
        const double* gy = s.weight_row(v, 2);
        const double* gz = s.weight_row(v, 3);
        WARPFEM_IVDEP
        for (int p = 0; p < cnt; ++p) {
          Wx[p] += gx[p];
          Wy[p] += gy[p];
          Wz[p] += gz[p];
        }
      }
    }
    for (int p = 0; p < cnt; ++p) iW[p] = 1 / iW[p], iWs[p] = iW[p] * isc;
    for (int v = 0; v < static_cast<int>(n); ++v) {
      const double* w = s.weight_row(v, 0);
      Real* f = phi.data() + v * N + p0;
      if constexpr (kGrad) {
        const double* gx = s.weight_row(v, 1);
        const double* gy = s.weight_row(v, 2);
        const double* gz = s.weight_row(v, 3);
        Real* dx = dphi_dx->data() + v * N + p0;
        Real* dy = dphi_dy->data() + v * N + p0;
        Real* dz = dphi_dz->data() + v * N + p0;
        WARPFEM_IVDEP
        for (int p = 0; p < cnt; ++p) {
          const Real ph = w[p] * iW[p];
          f[p] = ph;
          dx[p] = (gx[p] - ph * Wx[p]) * iWs[p];
          dy[p] = (gy[p] - ph * Wy[p]) * iWs[p];
          dz[p] = (gz[p] - ph * Wz[p]) * iWs[p];
        }
      } else {
        WARPFEM_IVDEP
        for (int p = 0; p < cnt; ++p) f[p] = w[p] * iW[p];
      }
    }
    for (int p = 0; p < cnt; ++p) {
      if (s.flag[p] == 0.0) continue;
      const Point<3> q(s.px[p], s.py[p], s.pz[p]);
      Real* rb = robust.data();
      coordinates_normalized(P, q, rb, kGrad ? rb + n : nullptr, rb + 2 * n, rb + 3 * n);
      for (Index v = 0; v < n; ++v) {
        phi(p0 + p, v) = rb[v];
        if constexpr (kGrad) {
          (*dphi_dx)(p0 + p, v) = rb[n + v] * isc;
          (*dphi_dy)(p0 + p, v) = rb[2 * n + v] * isc;
          (*dphi_dz)(p0 + p, v) = rb[3 * n + v] * isc;
        }
      }
    }
  }
}

WARPFEM_KERNEL_CLONES void values_blocks(const PolyhedronArrays& P, const Points<3>& x, Index first,
                                         Index last, MatrixX& phi) {
  evaluate_blocks<false>(P, x, first, last, phi, nullptr, nullptr, nullptr);
}

WARPFEM_KERNEL_CLONES void gradient_blocks(const PolyhedronArrays& P, const Points<3>& x, Index first,
                                           Index last, MatrixX& phi, MatrixX* dx, MatrixX* dy, MatrixX* dz) {
  evaluate_blocks<true>(P, x, first, last, phi, dx, dy, dz);
}

/// g = Σ_i φ_i values_i and, with kGrad, its Jacobian Σ_i values_i ∇φ_iᵀ for
/// the blocks first .. last: the weights' sums are taken per block straight
/// from the scratch, so no N × n coordinate matrix is written.
template <bool kGrad>
WARPFEM_KERNEL_INLINE void combine_blocks(const PolyhedronArrays& P, const Points<3>& x,
                                          const MatrixX& values, Index first, Index last, Points<3>& g,
                                          Jacobians<3>* J) {
  constexpr int B = detail::kPolyhedronBlock;
  const Index N = x.rows(), n = P.size();
  const Real isc = 1 / P.scale;
  detail::PolyhedronScratch s;
  s.resize(P);
  std::vector<Real> robust(static_cast<std::size_t>(4 * n));
  // Per point: W = Σ w_i, ∇W, A_r = Σ w_i v_ir and B_rc = Σ v_ir ∂_c w_i.
  alignas(64) double W[B], dW[3][B], A[3][B], Bm[9][B];
  for (Index p0 = first * B; p0 < std::min(N, last * B); p0 += B) {
    const int cnt = static_cast<int>(std::min<Index>(B, N - p0));
    load_block(P, x, p0, cnt, s);
    detail::polyhedron_block<kGrad>(P, cnt, s);
    add_near_plane_faces<kGrad>(P, cnt, s);
    for (int p = 0; p < B; ++p) {
      W[p] = 0;
      for (int r = 0; r < 3; ++r) dW[r][p] = A[r][p] = 0;
      for (int k = 0; k < 9; ++k) Bm[k][p] = 0;
    }
    for (int v = 0; v < static_cast<int>(n); ++v) {
      const double v0 = values(v, 0), v1 = values(v, 1), v2 = values(v, 2);
      const double* w = s.weight_row(v, 0);
      WARPFEM_IVDEP
      for (int p = 0; p < B; ++p) {
        W[p] += w[p];
        A[0][p] += v0 * w[p];
        A[1][p] += v1 * w[p];
        A[2][p] += v2 * w[p];
      }
      if constexpr (kGrad) {
        for (int c = 0; c < 3; ++c) {
          const double* gc = s.weight_row(v, 1 + c);
          WARPFEM_IVDEP
          for (int p = 0; p < B; ++p) {
            dW[c][p] += gc[p];
            Bm[c][p] += v0 * gc[p];
            Bm[3 + c][p] += v1 * gc[p];
            Bm[6 + c][p] += v2 * gc[p];
          }
        }
      }
    }
    for (int p = 0; p < cnt; ++p) {
      if (s.flag[p] != 0.0) {  // the robust path: coordinates first, then their combination
        const Point<3> q(s.px[p], s.py[p], s.pz[p]);
        Real* rb = robust.data();
        coordinates_normalized(P, q, rb, kGrad ? rb + n : nullptr, rb + 2 * n, rb + 3 * n);
        Point<3> gp = Point<3>::Zero();
        Matrix<3> Jp = Matrix<3>::Zero();
        for (Index v = 0; v < n; ++v) {
          const Point<3> value = values.row(v).transpose();
          gp += rb[v] * value;
          if constexpr (kGrad)
            Jp += value * Point<3>(rb[n + v], rb[2 * n + v], rb[3 * n + v]).transpose() * isc;
        }
        g.row(p0 + p) = gp.transpose();
        if constexpr (kGrad) set_jacobian_at<3>(*J, p0 + p, Jp);
        continue;
      }
      const double iW = 1 / W[p];
      double gr[3];
      for (int r = 0; r < 3; ++r) g(p0 + p, r) = gr[r] = A[r][p] * iW;
      if constexpr (kGrad) {
        // ∇φ_i = (∇w_i − φ_i ∇W) / W, so Σ_i v_i ∇φ_iᵀ = (B − g ∇Wᵀ) / W.
        const double iWs = iW * isc;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) (*J)(p0 + p, 3 * r + c) = (Bm[3 * r + c][p] - gr[r] * dW[c][p]) * iWs;
      }
    }
  }
}

WARPFEM_KERNEL_CLONES void combination_blocks(const PolyhedronArrays& P, const Points<3>& x,
                                              const MatrixX& values, Index first, Index last, Points<3>& g) {
  combine_blocks<false>(P, x, values, first, last, g, nullptr);
}

WARPFEM_KERNEL_CLONES void combination_gradient_blocks(const PolyhedronArrays& P, const Points<3>& x,
                                                       const MatrixX& values, Index first, Index last,
                                                       Points<3>& g, Jacobians<3>* J) {
  combine_blocks<true>(P, x, values, first, last, g, J);
}

}  // namespace

void mean_value_combination(const PolyhedronArrays& polyhedron, const Points<3>& x, const MatrixX& values,
                            Points<3>& g, Jacobians<3>* J) {
  require(values.rows() == polyhedron.size() && values.cols() == 3,
          "mean_value_combination: values must be n x 3 (one row per vertex)");
  const Index N = x.rows(), B = detail::kPolyhedronBlock;
  g.resize(N, 3);
  if (J) J->resize(N, 9);
  parallel_for((N + B - 1) / B, 4, [&](Index first, Index last) {
    if (J)
      combination_gradient_blocks(polyhedron, x, values, first, last, g, J);
    else
      combination_blocks(polyhedron, x, values, first, last, g);
  });
}

void mean_value_coordinates(const PolyhedronArrays& polyhedron, const Points<3>& x, MatrixX& phi) {
  const Index N = x.rows(), B = detail::kPolyhedronBlock;
  phi.resize(N, polyhedron.size());
  parallel_for((N + B - 1) / B, 4,
               [&](Index first, Index last) { values_blocks(polyhedron, x, first, last, phi); });
}

void mean_value_coordinates(const PolyhedronArrays& polyhedron, const Points<3>& x, MatrixX& phi,
                            MatrixX& dphi_dx, MatrixX& dphi_dy, MatrixX& dphi_dz) {
  const Index N = x.rows(), B = detail::kPolyhedronBlock, n = polyhedron.size();
  phi.resize(N, n);
  dphi_dx.resize(N, n);
  dphi_dy.resize(N, n);
  dphi_dz.resize(N, n);
  parallel_for((N + B - 1) / B, 4, [&](Index first, Index last) {
    gradient_blocks(polyhedron, x, first, last, phi, &dphi_dx, &dphi_dy, &dphi_dz);
  });
}

void mean_value_coordinates_at(const PolyhedronArrays& polyhedron, const Point<3>& x, Real* phi, Real* dx,
                               Real* dy, Real* dz) {
  const Point<3> q = normalized_point(polyhedron, x.x(), x.y(), x.z());
  coordinates_normalized(polyhedron, q, phi, dx, dy, dz);
  if (dx) {
    const Index n = polyhedron.size();
    for (Index v = 0; v < n; ++v) {
      dx[v] /= polyhedron.scale;
      dy[v] /= polyhedron.scale;
      dz[v] /= polyhedron.scale;
    }
  }
}

}  // namespace warpfem::mapping
