// Mean value coordinates of polyhedra: partition of unity, linear precision of
// values and gradients, the Lagrange property, linear interpolation on faces and
// edges, gradients against central differences (also on the plane of a distant
// face of a non-convex cage), agreement of the vectorized and robust paths, and
// invariance under similarity transforms.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <random>

#include "mapping/polyhedron_mean_value_coordinates.hpp"
#include "test_polyhedra.hpp"

namespace warpfem::mapping {
namespace {
using test::bumpy_sphere;
using test::unit_cube;

struct Values {
  MatrixX phi, dx, dy, dz;
};

Values batched(const PolyhedronArrays& A, const Points<3>& x) {
  Values v;
  mean_value_coordinates(A, x, v.phi, v.dx, v.dy, v.dz);
  return v;
}

Values robust(const PolyhedronArrays& A, const Point<3>& x) {
  const Index n = A.size();
  Values v;
  v.phi.resize(1, n), v.dx.resize(1, n), v.dy.resize(1, n), v.dz.resize(1, n);
  mean_value_coordinates_at(A, x, v.phi.data(), v.dx.data(), v.dy.data(), v.dz.data());
  return v;
}

/// Random points inside P (rejection by winding number), at least `margin` (relative) from the bounding box.
Points<3> interior_points(const Polyhedron& P, Index count, unsigned seed) {
  std::mt19937_64 rng(seed);
  const Point<3> lo = P.bbox_min(), hi = P.bbox_max();
  std::uniform_real_distribution<Real> u(0, 1);
  Points<3> x(count, 3);
  for (Index p = 0; p < count;) {
    const Point<3> q = lo + (hi - lo).cwiseProduct(Point<3>(u(rng), u(rng), u(rng)));
    if (test::winding_number(P, q) > 0.5) x.row(p++) = q.transpose();
  }
  return x;
}

Matrix<3> gradient_of_identity(const Polyhedron& P, const Values& v, Index p) {
  Matrix<3> J = Matrix<3>::Zero();  // Σ_i v_i ∇φ_i^T
  for (Index i = 0; i < P.vertex_count(); ++i) {
    const Point<3> g(v.dx(p, i), v.dy(p, i), v.dz(p, i));
    J += P.vertex(i) * g.transpose();
  }
  return J;
}

void expect_linear_precision(const Polyhedron& P, const Values& v, const Points<3>& x, Real tol) {
  for (Index p = 0; p < x.rows(); ++p) {
    Real s = 0;
    Point<3> f = Point<3>::Zero();
    for (Index i = 0; i < P.vertex_count(); ++i) {
      s += v.phi(p, i);
      f += v.phi(p, i) * P.vertex(i);
    }
    ASSERT_NEAR(s, 1, tol) << "point " << p;
    ASSERT_LT((f - x.row(p).transpose()).norm(), tol) << "point " << p;
    ASSERT_LT((gradient_of_identity(P, v, p) - Matrix<3>::Identity()).norm(), 1e3 * tol) << "point " << p;
  }
}

TEST(PolyhedronMeanValue, PartitionOfUnityAndLinearPrecision) {
  for (const Polyhedron& P : {unit_cube(), bumpy_sphere()}) {
    const PolyhedronArrays A(P);
    const Points<3> x = interior_points(P, 2000, 7);
    expect_linear_precision(P, batched(A, x), x, 1e-13);
  }
}

TEST(PolyhedronMeanValue, LagrangePropertyAtVertices) {
  const Polyhedron P = bumpy_sphere();
  const PolyhedronArrays A(P);
  Points<3> x(P.vertex_count(), 3);
  for (Index i = 0; i < P.vertex_count(); ++i) x.row(i) = P.vertex(i).transpose();
  const Values v = batched(A, x);
  for (Index p = 0; p < x.rows(); ++p)
    for (Index i = 0; i < P.vertex_count(); ++i) ASSERT_EQ(v.phi(p, i), p == i ? 1.0 : 0.0) << p << " " << i;
  for (Index p = 0; p < x.rows(); ++p) ASSERT_TRUE(v.dx.row(p).allFinite() && v.dz.row(p).allFinite());
}

TEST(PolyhedronMeanValue, LinearOnFacesAndEdges) {
  const Polyhedron P = bumpy_sphere();
  const PolyhedronArrays A(P);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(0.05, 0.9);
  const Index m = P.triangle_count();
  Points<3> x(2 * m, 3);
  MatrixX expected = MatrixX::Zero(2 * m, P.vertex_count());
  for (Index t = 0; t < m; ++t) {
    const auto& tr = P.triangle(t);
    Real l1 = u(rng), l2 = u(rng) * (1 - l1);
    const Real l0 = 1 - l1 - l2;
    x.row(t) = (l0 * P.vertex(tr[0]) + l1 * P.vertex(tr[1]) + l2 * P.vertex(tr[2])).transpose();
    expected(t, tr[0]) = l0, expected(t, tr[1]) = l1, expected(t, tr[2]) = l2;
    const Real a = u(rng);
    x.row(m + t) = ((1 - a) * P.vertex(tr[0]) + a * P.vertex(tr[1])).transpose();
    expected(m + t, tr[0]) = 1 - a, expected(m + t, tr[1]) = a;
  }
  const Values v = batched(A, x);
  EXPECT_LT((v.phi - expected).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_TRUE(v.dx.allFinite() && v.dy.allFinite() && v.dz.allFinite());
  // On a face φ is smooth across it: the gradient keeps linear precision.
  for (Index t = 0; t < m; ++t)
    EXPECT_LT((gradient_of_identity(P, v, t) - Matrix<3>::Identity()).norm(), 1e-9) << "face " << t;
}

/// Fourth-order central differences of φ (robust path) against the analytic gradient at x.
Real gradient_error(const PolyhedronArrays& A, const Point<3>& x, const Values& v, Index row, Real step) {
  Real err = 0, gmax = 0;
  for (int c = 0; c < 3; ++c) {
    Point<3> e = Point<3>::Zero();
    e[c] = step;
    const Values f1 = robust(A, x + e), f2 = robust(A, x + 2 * e), g1 = robust(A, x - e),
                 g2 = robust(A, x - 2 * e);
    const MatrixX& g = c == 0 ? v.dx : (c == 1 ? v.dy : v.dz);
    for (Index i = 0; i < A.size(); ++i) {
      const Real fd = (8 * (f1.phi(0, i) - g1.phi(0, i)) - (f2.phi(0, i) - g2.phi(0, i))) / (12 * step);
      err = std::max(err, std::abs(fd - g(row, i)));
      gmax = std::max(gmax, std::abs(g(row, i)));
    }
  }
  return err / gmax;
}

TEST(PolyhedronMeanValue, GradientsMatchCentralDifferences) {
  for (const Polyhedron& P : {unit_cube(), bumpy_sphere()}) {
    const PolyhedronArrays A(P);
    const Points<3> x = interior_points(P, 50, 11);
    const Values v = batched(A, x);
    for (Index p = 0; p < x.rows(); ++p)
      EXPECT_LT(gradient_error(A, x.row(p).transpose(), v, p, 1e-5), 1e-9) << p;
  }
}

/// Interior points on (or at relative distance `offset` from) the planes of
/// triangles that do not contain them, far from the triangle.
std::vector<std::pair<Point<3>, Index>> points_on_distant_planes(const Polyhedron& P, Real offset) {
  std::vector<std::pair<Point<3>, Index>> out;
  for (Index t = 0; t < P.triangle_count(); ++t) {
    const auto& tr = P.triangle(t);
    const Point<3> a = P.vertex(tr[0]), b = P.vertex(tr[1]), c = P.vertex(tr[2]);
    const Point<3> g = (a + b + c) / 3, nu = (b - a).cross(c - a).normalized();
    const Point<3> e1 = (b - a).normalized(), e2 = nu.cross(e1);
    bool found = false;
    for (int k = 0; k < 12 && !found; ++k) {
      const Real ang = 2 * std::numbers::pi * k / 12;
      for (const Real lambda : {0.5, 0.8, 1.1, 1.4}) {
        const Point<3> q = g + lambda * (std::cos(ang) * e1 + std::sin(ang) * e2) - offset * nu;
        if ((q - g).norm() < 1.5 * (b - a).norm()) continue;  // keep away from the triangle itself
        if (test::winding_number(P, q) < 0.5) continue;
        Real dmin = 1e9;  // and away from the surface
        for (Index v = 0; v < P.vertex_count(); ++v) dmin = std::min(dmin, (P.vertex(v) - q).norm());
        if (dmin < 0.05) continue;
        out.emplace_back(q, t);
        found = true;
        break;
      }
    }
  }
  return out;
}

TEST(PolyhedronMeanValue, GradientsOnPlanesOfDistantFacesOfNonConvexCage) {
  const Polyhedron P = bumpy_sphere();
  const PolyhedronArrays A(P);
  for (const Real offset : {0.0, 1e-12, 1e-9, 1e-6, 5e-5, 2e-4, 1e-3}) {
    const auto pts = points_on_distant_planes(P, offset);
    ASSERT_GT(pts.size(), 20u) << "the cage should have many faces whose planes cut its interior";
    Points<3> x(static_cast<Index>(pts.size()), 3);
    for (std::size_t k = 0; k < pts.size(); ++k) x.row(static_cast<Index>(k)) = pts[k].first.transpose();
    const Values v = batched(A, x);
    expect_linear_precision(P, v, x, 1e-13);
    Real worst = 0, worst_robust = 0;
    for (Index p = 0; p < x.rows(); ++p) {
      worst = std::max(worst, gradient_error(A, x.row(p).transpose(), v, p, 1e-5));
      const Values r = robust(A, x.row(p).transpose());
      const Real g = std::max({v.dx.row(p).cwiseAbs().maxCoeff(), v.dy.row(p).cwiseAbs().maxCoeff(), 1.0});
      worst_robust = std::max({worst_robust, (r.dx.row(0) - v.dx.row(p)).cwiseAbs().maxCoeff() / g,
                               (r.dy.row(0) - v.dy.row(p)).cwiseAbs().maxCoeff() / g,
                               (r.dz.row(0) - v.dz.row(p)).cwiseAbs().maxCoeff() / g});
    }
    EXPECT_LT(worst, 1e-9) << "offset " << offset << ", " << x.rows() << " points";
    std::printf("offset %g: %d points, central differences %.2e, vectorized vs robust %.2e\n", offset,
                static_cast<int>(x.rows()), worst, worst_robust);
    // The vectorized kernel hands points within 3e-4 (relative) of a plane to the
    // robust path; just above that its gradients lose a few more digits.
    EXPECT_LT(worst_robust, 1e-9) << "offset " << offset << ": vectorized and robust gradients differ";
  }
}

TEST(PolyhedronMeanValue, VectorizedAndRobustPathsAgree) {
  const Polyhedron P = bumpy_sphere();
  const PolyhedronArrays A(P);
  const Points<3> x = interior_points(P, 300, 5);
  const Values v = batched(A, x);
  for (Index p = 0; p < x.rows(); ++p) {
    const Values r = robust(A, x.row(p).transpose());
    ASSERT_LT((r.phi.row(0) - v.phi.row(p)).cwiseAbs().maxCoeff(), 1e-13) << p;
    const Real g = std::max(v.dx.row(p).cwiseAbs().maxCoeff(), 1.0);
    ASSERT_LT((r.dx.row(0) - v.dx.row(p)).cwiseAbs().maxCoeff(), 1e-10 * g) << p;
    ASSERT_LT((r.dy.row(0) - v.dy.row(p)).cwiseAbs().maxCoeff(), 1e-10 * g) << p;
    ASSERT_LT((r.dz.row(0) - v.dz.row(p)).cwiseAbs().maxCoeff(), 1e-10 * g) << p;
  }
}

TEST(PolyhedronMeanValue, InvariantUnderSimilarityTransforms) {
  const Polyhedron P = bumpy_sphere();
  const Points<3> x0 = interior_points(P, 200, 9);
  // Add points next to the surface, so that both paths are compared.
  Points<3> x(x0.rows() + P.vertex_count(), 3);
  x.topRows(x0.rows()) = x0;
  for (Index i = 0; i < P.vertex_count(); ++i) x.row(x0.rows() + i) = (0.999999 * P.vertex(i)).transpose();
  const Values v = batched(PolyhedronArrays(P), x);
  const Matrix<3> R = Eigen::AngleAxis<Real>(0.7, Point<3>(1, 2, 3).normalized()).toRotationMatrix();
  for (const Real s : {1e-6, 1e6}) {
    const Point<3> shift(3 * s, -s, 0.5 * s);
    std::vector<Point<3>> vertices;
    for (const auto& p : P.vertices()) vertices.push_back(s * R * p + shift);
    const Polyhedron Q = Polyhedron::checked(vertices, P.triangles(), "transformed");
    Points<3> y(x.rows(), 3);
    for (Index p = 0; p < x.rows(); ++p) y.row(p) = (s * R * x.row(p).transpose() + shift).transpose();
    const Values w = batched(PolyhedronArrays(Q), y);
    EXPECT_LT((w.phi - v.phi).cwiseAbs().maxCoeff(), 1e-11) << "scale " << s;
    // ∇φ transforms as R ∇φ / s.
    Real err = 0, gmax = 0;
    for (Index p = 0; p < x.rows(); ++p)
      for (Index i = 0; i < P.vertex_count(); ++i) {
        const Point<3> g(v.dx(p, i), v.dy(p, i), v.dz(p, i)), h(w.dx(p, i), w.dy(p, i), w.dz(p, i));
        err = std::max(err, (s * h - R * g).norm());
        gmax = std::max(gmax, g.norm());
      }
    EXPECT_LT(err / gmax, 1e-9) << "scale " << s;
  }
}

}  // namespace
}  // namespace warpfem::mapping

namespace warpfem::mapping {
namespace {

// mean_value_combination (one step of a mean value map, without the N x n
// matrices) gives φ · V and Σ_i v_i ∇φ_iᵀ of the coordinates, on every path:
// interior points, points next to the surface and the vertices (robust path),
// and points on the planes of distant faces (h-factored faces).
TEST(PolyhedronMeanValue, CombinationIsTheCoordinatesTimesTheValues) {
  const Polyhedron P = bumpy_sphere();
  const PolyhedronArrays A(P);
  const Points<3> inner = interior_points(P, 257, 11);  // not a multiple of the block
  const auto on_planes = points_on_distant_planes(P, 1e-9);
  Points<3> x(inner.rows() + P.vertex_count() + static_cast<Index>(on_planes.size()), 3);
  x.topRows(inner.rows()) = inner;
  for (Index i = 0; i < P.vertex_count(); ++i) x.row(inner.rows() + i) = (0.999999 * P.vertex(i)).transpose();
  for (std::size_t k = 0; k < on_planes.size(); ++k)
    x.row(inner.rows() + P.vertex_count() + static_cast<Index>(k)) = on_planes[k].first.transpose();
  MatrixX V(P.vertex_count(), 3);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-2, 2);
  for (Index i = 0; i < V.rows(); ++i) V.row(i) << u(rng), u(rng), u(rng);

  const Values v = batched(A, x);
  const Points<3> expected = v.phi * V;
  Points<3> g, g_only;
  Jacobians<3> J;
  mean_value_combination(A, x, V, g, &J);
  mean_value_combination(A, x, V, g_only);
  Real value_error = 0, jacobian_error = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    Matrix<3> expected_J;
    expected_J.col(0) = (v.dx.row(p) * V).transpose();
    expected_J.col(1) = (v.dy.row(p) * V).transpose();
    expected_J.col(2) = (v.dz.row(p) * V).transpose();
    value_error = std::max({value_error, (g.row(p) - expected.row(p)).cwiseAbs().maxCoeff(),
                            (g_only.row(p) - expected.row(p)).cwiseAbs().maxCoeff()});
    jacobian_error = std::max(jacobian_error, (jacobian_at<3>(J, p) - expected_J).cwiseAbs().maxCoeff() /
                                                  std::max(expected_J.cwiseAbs().maxCoeff(), 1.0));
  }
  // The sums run in another order (Σ w_i v_i / W against Σ (w_i / W) v_i):
  // rounding of order n ε |v| (n = 50 vertices, |v| ≤ 2), not more.
  EXPECT_LT(value_error, 1e-12);
  EXPECT_LT(jacobian_error, 1e-11);
  // Linear precision of the map itself: V = the vertices gives the identity.
  MatrixX I(P.vertex_count(), 3);
  for (Index i = 0; i < I.rows(); ++i) I.row(i) = P.vertex(i).transpose();
  mean_value_combination(A, x, I, g, &J);
  for (Index p = 0; p < x.rows(); ++p) {
    ASSERT_LT((g.row(p) - x.row(p)).cwiseAbs().maxCoeff(), 1e-12) << p;
    ASSERT_LT((jacobian_at<3>(J, p) - Matrix<3>::Identity()).cwiseAbs().maxCoeff(), 1e-9) << p;
  }
}

}  // namespace
}  // namespace warpfem::mapping
