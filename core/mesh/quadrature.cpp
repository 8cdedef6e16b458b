#include "core/mesh/quadrature.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <utility>

#include "core/error.hpp"

namespace warpfem {

QuadratureRule<1> gauss_legendre(int n) {
  require(n >= 1, "gauss_legendre: need at least one point");
  // Newton's method on the Legendre polynomial P_n from Tricomi's estimate of
  // each root: nodes and weights to full precision for any n (the eigenvectors
  // of Golub–Welsch lose a few digits of the weights as n grows).
  QuadratureRule<1> rule;
  rule.points.resize(n, 1);
  rule.weights.resize(n);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;  // P_{k-1}, P_k by the three-term recurrence
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1;
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    rule.points(i, 0) = 0.5 * (1 - x);              // roots come in decreasing x: points increase
    rule.weights(i) = 1 / ((1 - x * x) * dp * dp);  // 2 / ((1 - x²) P_n'(x)²) on [-1, 1], halved for [0, 1]
  }
  rule.degree = 2 * n - 1;
  return rule;
}

QuadratureRule<1> gauss_jacobi(int n, int alpha) {
  require(n >= 1 && alpha >= 0, "gauss_jacobi: need at least one point and alpha >= 0");
  // Golub–Welsch on the Jacobi matrix of the Jacobi polynomials P^(alpha, 0) on [-1, 1].
  const double a = alpha;
  MatrixX T = MatrixX::Zero(n, n);
  for (int k = 0; k < n; ++k) {
    const double s = 2.0 * k + a;
    T(k, k) = k == 0 ? -a / (a + 2.0) : -a * a / (s * (s + 2.0));
    if (k > 0)
      T(k, k - 1) = T(k - 1, k) =
          std::sqrt(4.0 * k * k * (k + a) * (k + a) / (s * s * (s + 1.0) * (s - 1.0)));
  }
  Eigen::SelfAdjointEigenSolver<MatrixX> eig(T);
  QuadratureRule<1> rule;
  rule.points.resize(n, 1);
  rule.weights.resize(n);
  for (int k = 0; k < n; ++k) {
    rule.points(k, 0) = 0.5 * (eig.eigenvalues()(k) + 1.0);
    const double v0 = eig.eigenvectors()(0, k);
    // Total weight on [0, 1]: integral of (1 - x)^alpha = 1 / (alpha + 1).
    rule.weights(k) = v0 * v0 / (a + 1.0);
  }
  rule.degree = 2 * n - 1;
  return rule;
}

namespace {
QuadratureRule<3> hexahedron_rule(int degree) {
  const auto g = gauss_legendre(degree / 2 + 1);
  const Index n = g.size();
  QuadratureRule<3> rule;
  rule.degree = g.degree;
  rule.points.resize(n * n * n, 3);
  rule.weights.resize(n * n * n);
  Index q = 0;
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n; ++j)
      for (Index i = 0; i < n; ++i, ++q) {
        rule.points.row(q) << g.points(i, 0), g.points(j, 0), g.points(k, 0);
        rule.weights(q) = g.weights(i) * g.weights(j) * g.weights(k);
      }
  return rule;
}

// Conical product (Stroud): (u, v, w) in [0,1]^3 -> (x, y, z) = (u (1-v)(1-w), v (1-w), w),
// Jacobian (1-v)(1-w)^2, absorbed into Gauss–Jacobi weights in v and w. A monomial
// of total degree p stays of degree <= p in each of u, v, w, so n = p/2 + 1 points
// per direction are exact to 2n - 1 >= p.
QuadratureRule<3> tetrahedron_rule(int degree) {
  const int n = degree / 2 + 1;
  const auto gu = gauss_legendre(n), gv = gauss_jacobi(n, 1), gw = gauss_jacobi(n, 2);
  QuadratureRule<3> rule;
  rule.degree = 2 * n - 1;
  rule.points.resize(static_cast<Index>(n) * n * n, 3);
  rule.weights.resize(static_cast<Index>(n) * n * n);
  Index q = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i, ++q) {
        const double u = gu.points(i, 0), v = gv.points(j, 0), w = gw.points(k, 0);
        rule.points.row(q) << u * (1.0 - v) * (1.0 - w), v * (1.0 - w), w;
        rule.weights(q) = gu.weights(i) * gv.weights(j) * gw.weights(k);
      }
  return rule;
}

// Quadrilateral: tensor Gauss. Triangle: symmetric rules up to degree 6, collapsed Gauss beyond.
QuadratureRule<2> rule_2d(CellType type, int degree) {
  QuadratureRule<2> rule;
  rule.degree = degree;
  if (type == CellType::quadrilateral) {
    const auto g = gauss_legendre(degree / 2 + 1);
    const Index n = g.size();
    rule.points.resize(n * n, 2);
    rule.weights.resize(n * n);
    for (Index i = 0; i < n; ++i)
      for (Index j = 0; j < n; ++j) {
        rule.points.row(i * n + j) << g.points(j, 0), g.points(i, 0);
        rule.weights(i * n + j) = g.weights(i) * g.weights(j);
      }
    return rule;
  }
  if (degree <= 6) {
    // Symmetric rules with fewer points than the collapsed Gauss rule (Strang–Fix / Dunavant):
    // every quadrature point costs one evaluation of the map, so this is what matters for WarpedGeometry.
    // Degree 4: 6 points (collapsed Gauss 9), 5: 7 (9), 6: 12 (16); all inside, positive weights.
    struct Orbit {
      double a, weight;  // points (a, a), (1 - 2a, a), (a, 1 - 2a); a = 1/3 is the centroid
    };
    std::vector<Orbit> orbits;
    struct FullOrbit {
      double a, b, weight;  // the 6 points with barycentric coordinates a permutation of (a, b, 1 - a - b)
    };
    std::vector<FullOrbit> full_orbits;
    if (degree <= 1)
      orbits = {{1.0 / 3.0, 1.0}};
    else if (degree == 2)
      orbits = {{1.0 / 6.0, 1.0 / 3.0}};
    else if (degree <= 4)
      orbits = {{0.445948490915965, 0.223381589678011}, {0.091576213509771, 0.109951743655322}};
    else if (degree == 5)
      orbits = {
          {1.0 / 3.0, 0.225}, {0.470142064105115, 0.132394152788506}, {0.101286507323456, 0.125939180544827}};
    else {
      orbits = {{0.249286745170910, 0.116786275726379}, {0.063089014491502, 0.050844906370207}};
      full_orbits = {{0.053145049844817, 0.310352451033784, 0.082851075618374}};
    }
    std::vector<std::array<double, 3>> pts;  // x, y, weight on the unit-area-normalized triangle
    for (const auto& o : orbits) {
      if (o.a == 1.0 / 3.0) {
        pts.push_back({o.a, o.a, o.weight});
      } else {
        pts.push_back({o.a, o.a, o.weight});
        pts.push_back({1 - 2 * o.a, o.a, o.weight});
        pts.push_back({o.a, 1 - 2 * o.a, o.weight});
      }
    }
    for (const auto& o : full_orbits) {
      const double c = 1 - o.a - o.b;
      for (const auto& [x, y] : {std::pair{o.a, o.b}, {o.b, o.a}, {o.a, c}, {c, o.a}, {o.b, c}, {c, o.b}})
        pts.push_back({x, y, o.weight});
    }
    rule.points.resize(static_cast<Index>(pts.size()), 2);
    rule.weights.resize(static_cast<Index>(pts.size()));
    for (std::size_t k = 0; k < pts.size(); ++k) {
      rule.points.row(static_cast<Index>(k)) << pts[k][0], pts[k][1];
      rule.weights(static_cast<Index>(k)) = 0.5 * pts[k][2];  // reference triangle area 1/2
    }
    return rule;
  }
  // Collapsed coordinates: (u, v) in [0,1]^2 -> (x, y) = (u (1 - v), v), Jacobian (1 - v).
  // Gauss in both directions with one extra point in v for the Jacobian factor.
  const auto gu = gauss_legendre(degree / 2 + 1);
  const auto gv = gauss_legendre((degree + 1) / 2 + 1);
  rule.points.resize(gu.size() * gv.size(), 2);
  rule.weights.resize(gu.size() * gv.size());
  Index k = 0;
  for (Index j = 0; j < gv.size(); ++j)
    for (Index i = 0; i < gu.size(); ++i, ++k) {
      const double u = gu.points(i, 0), v = gv.points(j, 0);
      rule.points.row(k) << u * (1.0 - v), v;
      rule.weights(k) = gu.weights(i) * gv.weights(j) * (1.0 - v);
    }
  return rule;
}

}  // namespace

template <int dim>
QuadratureRule<dim> cell_quadrature(CellType type, int degree) {
  require(degree >= 0, "cell_quadrature: negative degree");
  require(cell_dimension(type) == dim, "cell_quadrature<" + std::to_string(dim) + ">: " + to_string(type) +
                                           " cells have another dimension");
  if constexpr (dim == 2)
    return rule_2d(type, degree);
  else
    return type == CellType::hexahedron ? hexahedron_rule(degree) : tetrahedron_rule(degree);
}

template QuadratureRule<2> cell_quadrature<2>(CellType, int);
template QuadratureRule<3> cell_quadrature<3>(CellType, int);

int default_quadrature_degree(int order) {
  return 2 * order;
}

int measurement_quadrature_degree(int order) {
  return 2 * order + 2;
}

}  // namespace warpfem
