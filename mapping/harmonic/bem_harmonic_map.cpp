#include "mapping/harmonic/bem_harmonic_map.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace warpfem::mapping {
namespace {

constexpr Real kInv2Pi = 0.5 / std::numbers::pi;
constexpr int kMaxDepth = 60;
constexpr int kFarPoints = 4;  // Gauss points per element at ≥ kFarDistance element lengths
constexpr Real kFarDistance = 4;

/// Geometry of boundary element e (scaled): from node e to node e+1.
struct Element {
  Point<2> a, b, n;  // ends and outward normal
  Real L;
};

Element element(const BoundaryNodes& nodes, Index e) {
  const Index m = nodes.size();
  Element E;
  E.a = nodes.x[static_cast<std::size_t>(e)];
  E.b = nodes.x[static_cast<std::size_t>((e + 1) % m)];
  const Point<2> d = E.b - E.a;
  E.L = d.norm();
  E.n = Point<2>(d.y(), -d.x()) / E.L;
  return E;
}

Real segment_distance(const Point<2>& x, const Point<2>& a, const Point<2>& b) {
  const Point<2> e = b - a;
  const Real t = std::clamp((x - a).dot(e) / e.squaredNorm(), Real{0}, Real{1});
  return (a + t * e - x).norm();
}

/// Calls f(s, y, weight) for a quadrature of ∫_0^1 · L ds on element E, with
/// panels bisected toward x until each is at least its own length away.
template <class F>
void integrate_panel(const Point<2>& x, const Element& E, const QuadratureRule<1>& q, Real s0, Real s1,
                     int depth, F&& f) {
  const Point<2> pa = E.a + s0 * (E.b - E.a), pb = E.a + s1 * (E.b - E.a);
  const Real len = (s1 - s0) * E.L;
  if (depth >= kMaxDepth || segment_distance(x, pa, pb) >= len) {
    for (Index k = 0; k < q.size(); ++k) {
      const Real s = s0 + (s1 - s0) * q.points(k, 0);
      f(s, E.a + s * (E.b - E.a), q.weights(k) * len);
    }
    return;
  }
  const Real mid = 0.5 * (s0 + s1);
  integrate_panel(x, E, q, s0, mid, depth + 1, f);
  integrate_panel(x, E, q, mid, s1, depth + 1, f);
}

std::shared_ptr<const BemHarmonicCoordinates> solve(const Polygon& domain,
                                                    const std::vector<EdgeSpeed>& speeds_in,
                                                    const HarmonicOptions& o) {
  const Index n = domain.size();
  if (o.boundary_nodes < n)
    throw Error("bem: " + std::to_string(o.boundary_nodes) + " boundary nodes are fewer than the " +
                    std::to_string(n) + " vertices of " + domain.name(),
                {.file = "", .key_path = "map.boundary_nodes", .hint = "use at least 4 nodes per vertex"});
  require(o.quadrature_points >= 1 && o.quadrature_points <= 64,
          "bem: quadrature_points must lie in [1, 64]");
  const std::vector<EdgeSpeed> speeds = speeds_for(domain, speeds_in);
  auto c = std::make_shared<BemHarmonicCoordinates>();
  c->center = 0.5 * (domain.bbox_min() + domain.bbox_max());
  c->scale = diameter(domain);
  c->snap = o.snap_distance;
  c->rule = gauss_legendre(o.quadrature_points);
  c->nodes = sample_boundary(domain, o.boundary_nodes);
  for (auto& x : c->nodes.x) x = (x - c->center) / c->scale;
  const Index m = c->nodes.size();
  c->element_length.assign(static_cast<std::size_t>(n), 0);
  for (Index j = 0; j < m; ++j) {
    const Index e = c->nodes.at[static_cast<std::size_t>(j)].edge;
    c->element_length[static_cast<std::size_t>(e)] = std::max(
        c->element_length[static_cast<std::size_t>(e)],
        (c->nodes.x[static_cast<std::size_t>((j + 1) % m)] - c->nodes.x[static_cast<std::size_t>(j)]).norm());
  }

  c->c.resize(m, n);
  std::vector<Real> w(static_cast<std::size_t>(n));
  for (Index j = 0; j < m; ++j) {
    boundary_weights(speeds, c->nodes.at[static_cast<std::size_t>(j)], w.data(), n);
    for (Index k = 0; k < n; ++k) c->c(j, k) = w[static_cast<std::size_t>(k)];
  }

  // Single-layer coefficients of d at the start (Gs) and end (Ge) of each element.
  MatrixX Gs = MatrixX::Zero(m, m), Ge = MatrixX::Zero(m, m), H = MatrixX::Zero(m, m);
  for (Index e = 0; e < m; ++e) {
    const Element E = element(c->nodes, e);
    const Index e1 = (e + 1) % m;
    const Real self_near = -kInv2Pi * E.L * (0.5 * std::log(E.L) - 0.75);  // hat = 1 at x_j
    const Real self_far = -kInv2Pi * E.L * (0.5 * std::log(E.L) - 0.25);   // hat = 0 at x_j
    for (Index j = 0; j < m; ++j) {
      if (j == e) {
        Gs(j, e) += self_near;
        Ge(j, e) += self_far;
        continue;
      }
      if (j == e1) {
        Ge(j, e) += self_near;
        Gs(j, e) += self_far;
        continue;
      }
      const Point<2> xj = c->nodes.x[static_cast<std::size_t>(j)];
      integrate_panel(xj, E, c->rule, 0, 1, 0, [&](Real s, const Point<2>& y, Real wt) {
        const Point<2> r = xj - y;
        const Real r2 = r.squaredNorm();
        const Real g = -kInv2Pi * 0.5 * std::log(r2) * wt;
        const Real k = kInv2Pi * r.dot(E.n) / r2 * wt;
        Gs(j, e) += (1 - s) * g;
        Ge(j, e) += s * g;
        H(j, e) += (1 - s) * k;
        H(j, e1) += s * k;
      });
    }
  }

  // At a convex corner the harmonic φ is C¹, so ∇φ there follows from the two
  // tangential derivatives of the data; ∂φ/∂n takes a known value on each side
  // (a double node). Elsewhere ∂φ/∂n is continuous and unknown.
  MatrixX Kp = MatrixX::Zero(m, n), Km = MatrixX::Zero(m, n);  // d on the edge after / before node j
  std::vector<Index> unknown(static_cast<std::size_t>(m), -1);
  Index nu = 0;
  for (Index j = 0; j < m; ++j) {
    const BoundaryPoint& at = c->nodes.at[static_cast<std::size_t>(j)];
    const Index v = at.edge;
    const Point<2> t1 = domain.vertex(v + 1) - domain.vertex(v), t0 = domain.vertex(v) - domain.vertex(v - 1);
    const Real L1 = t1.norm(), L0 = t0.norm();
    const bool convex = at.t == 0 && t0.x() * t1.y() - t0.y() * t1.x() > 1e-6 * L0 * L1;
    if (!convex) {
      unknown[static_cast<std::size_t>(j)] = nu++;
      continue;
    }
    // scaled frame: lengths divide by scale, so derivatives multiply by it
    Matrix<2> T;
    T << t0.transpose() / L0, t1.transpose() / L1;
    const Real ds1 = edge_speed(speeds[static_cast<std::size_t>(v)], 1e-7) / 1e-7;  // s'(0) of edge v
    const std::size_t vp = static_cast<std::size_t>(domain.wrap(v - 1));
    const Real ds0 = (1 - edge_speed(speeds[vp], 1 - 1e-7)) / 1e-7;  // s'(1) of edge v−1
    const Point<2> n1 = Point<2>(t1.y(), -t1.x()) / L1, n0 = Point<2>(t0.y(), -t0.x()) / L0;
    for (Index k = 0; k < n; ++k) {
      auto val = [&](Index i) { return static_cast<Real>(i == k); };
      const Point<2> rhs(ds0 / L0 * (val(v) - val(domain.wrap(v - 1))),
                         ds1 / L1 * (val(domain.wrap(v + 1)) - val(v)));
      const Point<2> grad = T.inverse() * rhs * c->scale;
      Kp(j, k) = grad.dot(n1);
      Km(j, k) = grad.dot(n0);
    }
  }

  const VectorX omega = -H.rowwise().sum();
  const MatrixX full_rhs = omega.asDiagonal() * c->c + H * c->c;
  MatrixX A = MatrixX::Zero(nu, nu), rhs(nu, n);
  for (Index j = 0; j < m; ++j) {
    const Index r = unknown[static_cast<std::size_t>(j)];
    if (r < 0) continue;
    rhs.row(r) = full_rhs.row(j);
    for (Index e = 0; e < m; ++e) {
      const Index e1 = (e + 1) % m;
      const Index us = unknown[static_cast<std::size_t>(e)], ue = unknown[static_cast<std::size_t>(e1)];
      if (us >= 0)
        A(r, us) += Gs(j, e);
      else
        rhs.row(r) -= Gs(j, e) * Kp.row(e);
      if (ue >= 0)
        A(r, ue) += Ge(j, e);
      else
        rhs.row(r) -= Ge(j, e) * Km.row(e1);
    }
  }
  const MatrixX u = A.partialPivLu().solve(rhs);
  if (!u.allFinite())
    throw Error(
        "bem: the boundary system of " + domain.name() + " is singular",
        {.file = "", .key_path = "map.boundary_nodes", .hint = "change the number of boundary nodes"});
  c->d_start.resize(m, n);
  c->d_end.resize(m, n);
  for (Index e = 0; e < m; ++e) {
    const Index e1 = (e + 1) % m;
    const Index us = unknown[static_cast<std::size_t>(e)], ue = unknown[static_cast<std::size_t>(e1)];
    c->d_start.row(e) = us >= 0 ? MatrixX(u.row(us)) : MatrixX(Kp.row(e));
    c->d_end.row(e) = ue >= 0 ? MatrixX(u.row(ue)) : MatrixX(Km.row(e1));
  }
  return c;
}

}  // namespace

BemHarmonicMap::BemHarmonicMap(const Polygon& domain, const Polygon& image,
                               const std::vector<EdgeSpeed>& speeds, const HarmonicOptions& options)
    : BemHarmonicMap(solve(domain, speeds, options), domain, image, speeds) {}

BemHarmonicMap::BemHarmonicMap(std::shared_ptr<const BemHarmonicCoordinates> coordinates,
                               const Polygon& domain, const Polygon& image,
                               const std::vector<EdgeSpeed>& speeds)
    : HarmonicMap(domain, image, speeds), coords_(std::move(coordinates)) {
  const auto W = image_vertices();
  C_ = coords_->c * W;
  Ds_ = coords_->d_start * W;
  De_ = coords_->d_end * W;
  fill_table(near_, coords_->rule);
  fill_table(far_, gauss_legendre(std::min<int>(kFarPoints, static_cast<int>(coords_->rule.size()))));
}

void BemHarmonicMap::fill_table(QuadratureTable& t, const QuadratureRule<1>& q) const {
  const Index m = coords_->nodes.size();
  const Index nq = q.size();
  t.per_element = nq;
  for (VectorX* v : {&t.x, &t.y, &t.nx, &t.ny, &t.w, &t.c0, &t.c1, &t.d0, &t.d1}) v->resize(m * nq);
  for (Index e = 0; e < m; ++e) {
    const Element E = element(coords_->nodes, e);
    const Index e1 = (e + 1) % m;
    for (Index k = 0; k < nq; ++k) {
      const Real s = q.points(k, 0);
      const Index i = e * nq + k;
      const Point<2> y = E.a + s * (E.b - E.a);
      t.x(i) = y.x();
      t.y(i) = y.y();
      t.nx(i) = E.n.x();
      t.ny(i) = E.n.y();
      t.w(i) = q.weights(k) * E.L;
      t.c0(i) = (1 - s) * C_(e, 0) + s * C_(e1, 0);
      t.c1(i) = (1 - s) * C_(e, 1) + s * C_(e1, 1);
      t.d0(i) = (1 - s) * Ds_(e, 0) + s * De_(e, 0);
      t.d1(i) = (1 - s) * Ds_(e, 1) + s * De_(e, 1);
    }
  }
}

void BemHarmonicMap::representation(const Point<2>& xs, Point<2>& phi, Matrix<2>* J) const {
  const Index m = coords_->nodes.size();
  Real p0 = 0, p1 = 0, j00 = 0, j01 = 0, j10 = 0, j11 = 0;
  auto add = [&](Real yx, Real yy, Real nx, Real ny, Real wt, Real c0, Real c1, Real d0, Real d1) {
    const Real rx = xs.x() - yx, ry = xs.y() - yy;
    const Real r2 = rx * rx + ry * ry, inv = 1 / r2;
    const Real g = -0.5 * std::log(r2);         // 2π G
    const Real rn = (rx * nx + ry * ny) * inv;  // 2π ∂G/∂n_y
    p0 += wt * (d0 * g - c0 * rn);
    p1 += wt * (d1 * g - c1 * rn);
    if (J) {
      const Real gx = -rx * inv, gy = -ry * inv;                                        // 2π ∇G
      const Real kx = nx * inv - 2 * rn * rx * inv, ky = ny * inv - 2 * rn * ry * inv;  // 2π ∇(∂G/∂n)
      j00 += wt * (d0 * gx - c0 * kx);
      j01 += wt * (d0 * gy - c0 * ky);
      j10 += wt * (d1 * gx - c1 * kx);
      j11 += wt * (d1 * gy - c1 * ky);
    }
  };
  auto add_table = [&](const QuadratureTable& t, Index e) {
    for (Index i = e * t.per_element; i < (e + 1) * t.per_element; ++i)
      add(t.x(i), t.y(i), t.nx(i), t.ny(i), t.w(i), t.c0(i), t.c1(i), t.d0(i), t.d1(i));
  };
  for (Index e = 0; e < m; ++e) {
    const Element E = element(coords_->nodes, e);
    // far: ≥ kFarDistance lengths away (checked on the midpoint), few Gauss points suffice
    if ((xs - 0.5 * (E.a + E.b)).norm() >= (kFarDistance + 0.5) * E.L) {
      add_table(far_, e);
      continue;
    }
    if (segment_distance(xs, E.a, E.b) >= E.L) {
      add_table(near_, e);
      continue;
    }
    const Index e1 = (e + 1) % m;
    integrate_panel(xs, E, coords_->rule, 0, 1, 0, [&](Real s, const Point<2>& y, Real wt) {
      add(y.x(), y.y(), E.n.x(), E.n.y(), wt, (1 - s) * C_(e, 0) + s * C_(e1, 0),
          (1 - s) * C_(e, 1) + s * C_(e1, 1), (1 - s) * Ds_(e, 0) + s * De_(e, 0),
          (1 - s) * Ds_(e, 1) + s * De_(e, 1));
    });
  }
  phi = Point<2>(p0, p1) * kInv2Pi;
  if (J) *J = (Matrix<2>() << j00, j01, j10, j11).finished() * kInv2Pi;
}

void BemHarmonicMap::eval_point(const Point<2>& x, Point<2>& phi, Matrix<2>* J) const {
  const Real scale = coords_->scale;
  Real dist = 0;
  const BoundaryPoint bp = closest_boundary_point(domain(), x, &dist);
  if (dist / scale >= coords_->snap) {
    representation((x - coords_->center) / scale, phi, J);  // φ and J_φ of the same point
    if (J) *J /= scale;
    return;
  }
  phi = boundary_value(image(), speeds(), bp);
  if (!J) return;
  // On ∂Ω the representation's gradient is singular; J_φ is its limit from
  // inside, taken one snap distance inside (along the bisector at a corner).
  const Polygon& P = domain();
  auto inward = [&](Index i) {
    const Point<2> e = P.vertex(i + 1) - P.vertex(i);
    return Point<2>(-e.y(), e.x()).normalized();
  };
  const Real step = 2 * coords_->snap * scale;
  const bool at_vertex = bp.t <= 0 || bp.t >= 1;
  const Index v = bp.t < 0.5 ? bp.edge : bp.edge + 1;
  const Point<2> base = boundary_position(P, bp);
  const Point<2> q = at_vertex ? Point<2>(P.vertex(v) + step * (inward(v - 1) + inward(v)).normalized())
                               : Point<2>(base + step * inward(bp.edge));
  Point<2> unused;
  representation((q - coords_->center) / scale, unused, J);
  *J /= scale;
}

HarmonicMapPtr BemHarmonicMap::with_image(const Polygon& image) const {
  return std::make_shared<const BemHarmonicMap>(coords_, domain(), image, speeds());
}

}  // namespace warpfem::mapping
