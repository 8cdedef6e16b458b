// Mean value, Wachspress and discrete harmonic coordinates: the defining
// properties (thesis eq. 1.2), gradients, and the boundary cases.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mapping/barycentric_coordinates.hpp"
#include "mapping/barycentric_step.hpp"
#include "mapping/detail/mean_value_avx512.hpp"
#include "mapping/mean_value_coordinates.hpp"
#include "mapping/polygon_sampling.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

struct Case {
  Coordinates type;
  Polygon (*make)();
  const char* name;
};

class CoordinateProperties : public ::testing::TestWithParam<Case> {};

Points<2> one_point(Real x, Real y) {
  Points<2> p(1, 2);
  p << x, y;
  return p;
}

TEST_P(CoordinateProperties, PartitionOfUnityAndLinearPrecision) {
  const Polygon P = GetParam().make();
  const Points<2> x = bijectivity_sample(P, 24);
  ASSERT_GT(x.rows(), 300);
  const BarycentricValues v = barycentric_coordinates(GetParam().type, P, x);
  Matrix<2> V;
  for (Index p = 0; p < x.rows(); ++p) {
    ASSERT_NEAR(v.phi.row(p).sum(), 1.0, 1e-12) << "point " << p;
    Real sx = 0, sy = 0, gx = 0, gy = 0;
    for (Index i = 0; i < P.size(); ++i) {
      sx += v.phi(p, i) * P.vertex(i).x();
      sy += v.phi(p, i) * P.vertex(i).y();
      gx += v.dphi_dx(p, i);
      gy += v.dphi_dy(p, i);
    }
    ASSERT_NEAR(sx, x(p, 0), 1e-12) << "point " << p;
    ASSERT_NEAR(sy, x(p, 1), 1e-12) << "point " << p;
    // gradient of the partition of unity vanishes (relative to the gradient size)
    const Real scale = 1 + v.dphi_dx.row(p).cwiseAbs().maxCoeff() + v.dphi_dy.row(p).cwiseAbs().maxCoeff();
    ASSERT_NEAR(gx / scale, 0.0, 1e-10);
    ASSERT_NEAR(gy / scale, 0.0, 1e-10);
  }
}

TEST_P(CoordinateProperties, LagrangePropertyAtAndNearVertices) {
  const Polygon P = GetParam().make();
  const Index n = P.size();
  for (Index j = 0; j < n; ++j) {
    const Point<2> v = P.vertex(j);
    const BarycentricValues at = barycentric_coordinates(GetParam().type, P, one_point(v.x(), v.y()));
    for (Index i = 0; i < n; ++i) EXPECT_EQ(at.phi(0, i), i == j ? 1.0 : 0.0) << "vertex " << j;
    EXPECT_TRUE(at.dphi_dx.allFinite() && at.dphi_dy.allFinite());
    // 1e-14 towards the polygon's centre of its neighbours
    const Point<2> c = (P.vertex(j - 1) + P.vertex(j + 1)) / 2;
    const Point<2> q = v + 1e-14 * (c - v).normalized();
    const BarycentricValues near = barycentric_coordinates(GetParam().type, P, one_point(q.x(), q.y()));
    EXPECT_TRUE(near.phi.allFinite() && near.dphi_dx.allFinite() && near.dphi_dy.allFinite())
        << "vertex " << j;
    EXPECT_NEAR(near.phi(0, j), 1.0, 1e-10) << "vertex " << j;
  }
}

TEST_P(CoordinateProperties, LinearOnEdgesAndStableNextToThem) {
  const Polygon P = GetParam().make();
  const Index n = P.size();
  for (Index i = 0; i < n; ++i) {
    const Point<2> a = P.vertex(i), b = P.vertex(i + 1);
    const Point<2> e = b - a, inward = Point<2>(-e.y(), e.x()).normalized();
    for (Real mu : {0.1, 0.37, 0.5, 0.93}) {
      const Point<2> on = (1 - mu) * a + mu * b;
      for (Real d : {0.0, 1e-14, 1e-12}) {
        const Point<2> q = on + d * inward;
        const BarycentricValues v = barycentric_coordinates(GetParam().type, P, one_point(q.x(), q.y()));
        ASSERT_TRUE(v.phi.allFinite() && v.dphi_dx.allFinite() && v.dphi_dy.allFinite())
            << "edge " << i << " mu " << mu << " d " << d;
        for (Index k = 0; k < n; ++k) {
          const Real expect = k == i ? 1 - mu : (k == P.wrap(i + 1) ? mu : 0.0);
          ASSERT_NEAR(v.phi(0, k), expect, d == 0 ? 1e-14 : 1e-9)
              << "edge " << i << " mu " << mu << " d " << d;
        }
      }
      // The gradient has a limit at the edge: values at 1e-13 and 1e-9 agree.
      const Point<2> q1 = on + 1e-13 * inward, q2 = on + 1e-9 * inward;
      const BarycentricValues v1 = barycentric_coordinates(GetParam().type, P, one_point(q1.x(), q1.y()));
      const BarycentricValues v2 = barycentric_coordinates(GetParam().type, P, one_point(q2.x(), q2.y()));
      const Real g = 1 + v2.dphi_dx.cwiseAbs().maxCoeff() + v2.dphi_dy.cwiseAbs().maxCoeff();
      EXPECT_LT((v1.dphi_dx - v2.dphi_dx).cwiseAbs().maxCoeff() / g, 1e-6) << "edge " << i << " mu " << mu;
      EXPECT_LT((v1.dphi_dy - v2.dphi_dy).cwiseAbs().maxCoeff() / g, 1e-6) << "edge " << i << " mu " << mu;
    }
  }
}

TEST_P(CoordinateProperties, GradientsMatchCentralDifferences) {
  const Polygon P = GetParam().make();
  const Points<2> x = grid_sample(P, 16);
  const BarycentricValues v = barycentric_coordinates(GetParam().type, P, x);
  const Real h = 1e-5 * P.perimeter() / static_cast<Real>(P.size());
  Points<2> xp = x, xm = x, yp = x, ym = x;
  xp.col(0).array() += h;
  xm.col(0).array() -= h;
  yp.col(1).array() += h;
  ym.col(1).array() -= h;
  const auto c = GetParam().type;
  const MatrixX fdx =
      (barycentric_coordinates(c, P, xp, false).phi - barycentric_coordinates(c, P, xm, false).phi) / (2 * h);
  const MatrixX fdy =
      (barycentric_coordinates(c, P, yp, false).phi - barycentric_coordinates(c, P, ym, false).phi) / (2 * h);
  Real worst = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    const Real g = std::max(v.dphi_dx.row(p).cwiseAbs().maxCoeff(), v.dphi_dy.row(p).cwiseAbs().maxCoeff());
    const Real e = std::max((v.dphi_dx.row(p) - fdx.row(p)).cwiseAbs().maxCoeff(),
                            (v.dphi_dy.row(p) - fdy.row(p)).cwiseAbs().maxCoeff());
    worst = std::max(worst, e / g);
  }
  std::printf("[ %s ] worst relative gradient error vs central differences: %.2e (%ld points)\n",
              GetParam().name, worst, static_cast<long>(x.rows()));
  EXPECT_LE(worst, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(
    Mapping, CoordinateProperties,
    ::testing::Values(Case{Coordinates::mean_value, &test::concave32, "mean_value_concave32"},
                      Case{Coordinates::mean_value, [] { return test::star(); }, "mean_value_star"},
                      Case{Coordinates::mean_value, [] { return test::dart(); }, "mean_value_dart"},
                      Case{Coordinates::wachspress, &test::convex6, "wachspress_hexagon"},
                      Case{Coordinates::discrete_harmonic, &test::convex6, "discrete_harmonic_hexagon"},
                      Case{Coordinates::discrete_harmonic, &test::diamond, "discrete_harmonic_diamond"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(MeanValueCoordinates, FastKernelAgreesWithRobustFormula) {
  const Polygon P = test::concave32();
  const PolygonArrays A(P);
  const Points<2> x = bijectivity_sample(P, 20);
  MatrixX phi, dx, dy;
  mean_value_coordinates(A, x, phi, dx, dy);
  std::vector<Real> r(3 * 32), work;
  Real worst = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    mean_value_coordinates_at(A, x(p, 0), x(p, 1), r.data(), r.data() + 32, r.data() + 64, work);
    const Real g = 1 + dx.row(p).cwiseAbs().maxCoeff() + dy.row(p).cwiseAbs().maxCoeff();
    for (Index i = 0; i < 32; ++i) {
      worst = std::max(worst, std::abs(phi(p, i) - r[i]));
      worst = std::max(worst, std::abs(dx(p, i) - r[32 + i]) / g);
      worst = std::max(worst, std::abs(dy(p, i) - r[64 + i]) / g);
    }
  }
  EXPECT_LT(worst, 1e-9);
}

/// Runs `body` once with the AVX-512 kernels (if this CPU has them) and once with
/// the portable kernels, restoring the previous choice.
template <class Body>
void with_both_kernels(Body&& body) {
  const bool before = detail::set_avx512_kernels_enabled(true);
  const bool have_avx512 = detail::avx512_kernels_enabled();
  body();
  detail::set_avx512_kernels_enabled(false);
  body();
  detail::set_avx512_kernels_enabled(before);
  if (!have_avx512) GTEST_LOG_(INFO) << "this CPU has no AVX-512F: only the portable kernels ran";
}

/// Wavy n-gons: 150 vertices are buffered one group of points at a time by the
/// AVX-512 kernel, 300 exceed its buffer (normalized in place in the output).
Polygon wavy(int n) {
  std::vector<Point<2>> v;
  for (int i = 0; i < n; ++i) {
    const Real a = 2 * std::numbers::pi * i / n, r = 1 + 0.2 * std::sin(5 * a);
    v.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return Polygon::checked(v, "wavy " + std::to_string(n) + "-gon");
}
Polygon wavy150() {
  return wavy(150);
}
Polygon wavy300() {
  return wavy(300);
}

class KernelAgreement : public ::testing::TestWithParam<Polygon (*)()> {};

TEST_P(KernelAgreement, Avx512AndPortableKernelsAgree) {
  const Polygon P = GetParam()();
  const PolygonArrays A(P);
  // Interior sample clustered at the vertices and edges (flagged points take the robust
  // path in both kernels), plus an odd count so the last vector is partly masked.
  const Points<2> x = bijectivity_sample(P, 21);
  ASSERT_NE(x.rows() % 8, 0);
  std::vector<MatrixX> phi, dx, dy, vals;
  std::vector<Points<2>> f, f_only;
  std::vector<Jacobians<2>> J;
  std::vector<Point<2>> moved = P.vertices();
  for (std::size_t i = 0; i < moved.size(); ++i)
    moved[i] +=
        Point<2>(0.05 * std::sin(3.0 * static_cast<Real>(i)), 0.04 * std::cos(5.0 * static_cast<Real>(i)));
  const BarycentricStep warp(P, moved, Coordinates::mean_value);
  with_both_kernels([&] {
    phi.emplace_back(), dx.emplace_back(), dy.emplace_back(), vals.emplace_back();
    mean_value_coordinates(A, x, phi.back(), dx.back(), dy.back());
    mean_value_coordinates(A, x, vals.back());
    f.emplace_back(), J.emplace_back(), f_only.emplace_back();
    warp.apply(x, f.back(), &J.back());
    warp.apply(x, f_only.back(), nullptr);  // the map step without its Jacobian
  });
  EXPECT_LT((phi[0] - phi[1]).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((vals[0] - vals[1]).cwiseAbs().maxCoeff(), 1e-13);
  const Real gscale = 1 + dx[1].cwiseAbs().maxCoeff() + dy[1].cwiseAbs().maxCoeff();
  // Gradients next to an edge are large and cancel: a few 1e-12 is rounding.
  EXPECT_LT((dx[0] - dx[1]).cwiseAbs().maxCoeff() / gscale, 1e-11);
  EXPECT_LT((dy[0] - dy[1]).cwiseAbs().maxCoeff() / gscale, 1e-11);
  EXPECT_LT((f[0] - f[1]).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((f_only[0] - f_only[1]).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT((f_only[0] - f[0]).cwiseAbs().maxCoeff(), 1e-15);
  // J sums n gradients of the kind above (1.06e-12 on the 300-gon).
  EXPECT_LT((J[0] - J[1]).cwiseAbs().maxCoeff() / (1 + J[1].cwiseAbs().maxCoeff()), 1e-11);
}

INSTANTIATE_TEST_SUITE_P(MeanValueCoordinates, KernelAgreement,
                         ::testing::Values(&test::concave32, &wavy150, &wavy300));

TEST(MeanValueCoordinates, ValuesOnlyEqualsValuesWithGradients) {
  const Polygon P = test::star();
  const Points<2> x = bijectivity_sample(P, 20);
  MatrixX a, b, dx, dy;
  mean_value_coordinates(PolygonArrays(P), x, a);
  mean_value_coordinates(PolygonArrays(P), x, b, dx, dy);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ConvexCoordinates, RefuseConcavePolygonsNamingTheReflexVertex) {
  const Polygon P = test::dart();  // vertex 2 at (-0.6, 0) is reflex
  for (Coordinates c : {Coordinates::wachspress, Coordinates::discrete_harmonic}) {
    try {
      barycentric_coordinates(c, P, one_point(-0.5, 0.2));
      FAIL() << "expected warpfem::Error for " << to_string(c);
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("dart"), std::string::npos) << what;
      EXPECT_NE(what.find("reflex vertex 2"), std::string::npos) << what;
      EXPECT_NE(what.find(to_string(c)), std::string::npos) << what;
    }
  }
  // Wachspress also refuses collinear vertices (their weight would vanish).
  const Polygon square =
      test::polygon({{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}}, "square with a mid-edge vertex");
  EXPECT_THROW(barycentric_coordinates(Coordinates::wachspress, square, one_point(1, 1)), Error);
  EXPECT_NO_THROW(barycentric_coordinates(Coordinates::discrete_harmonic, square, one_point(1, 1)));
  EXPECT_NO_THROW(barycentric_coordinates(Coordinates::mean_value, square, one_point(1, 1)));
}

// The gradient at a vertex is the one-sided value from a point just inside. At a
// straight vertex (discrete harmonic allows them) the bisector of the two edges
// vanishes, and next to an edge 1e-9 long the step inside is below the vertex snap
// distance: both once recursed without end (a stack overflow found by fuzz_make_map).
TEST(ConvexCoordinates, GradientsAtAStraightVertexAndNextToAShortEdge) {
  auto check_gradients = [](Coordinates type, const Polygon& P, Real tolerance) {
    const Index n = P.size();
    for (Index j = 0; j < n; ++j) {
      const Point<2> v = P.vertex(j);
      const BarycentricValues at = barycentric_coordinates(type, P, one_point(v.x(), v.y()));
      ASSERT_TRUE(at.dphi_dx.allFinite() && at.dphi_dy.allFinite()) << P.name() << ", vertex " << j;
      // The gradients reproduce linear functions: Σ∇φ_i = 0, Σ v_i ⊗ ∇φ_i = I.
      Matrix<2> V = Matrix<2>::Zero();
      Point<2> g = Point<2>::Zero();
      for (Index i = 0; i < n; ++i) {
        const Point<2> d(at.dphi_dx(0, i), at.dphi_dy(0, i));
        g += d;
        V += P.vertex(i) * d.transpose();
      }
      EXPECT_LT(g.norm(), tolerance) << to_string(type) << ", " << P.name() << ", vertex " << j;
      EXPECT_LT((V - Matrix<2>::Identity()).norm(), tolerance)
          << to_string(type) << ", " << P.name() << ", vertex " << j;
    }
  };
  const Polygon straight =
      test::polygon({{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}}, "square with a mid-edge vertex");
  check_gradients(Coordinates::discrete_harmonic, straight, 1e-6);
  // The gradient at the straight vertex is the limit from inside.
  const BarycentricValues at =
      barycentric_coordinates(Coordinates::discrete_harmonic, straight, one_point(1, 0));
  const BarycentricValues in =
      barycentric_coordinates(Coordinates::discrete_harmonic, straight, one_point(1, 1e-6));
  EXPECT_LT((at.dphi_dx - in.dphi_dx).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT((at.dphi_dy - in.dphi_dy).cwiseAbs().maxCoeff(), 1e-4);

  const Polygon short_edge = test::polygon({{0, 0}, {1, 0}, {1, 1 - 1e-9}, {1 - 1e-9, 1}, {0, 1}},
                                           "square with a corner cut by a 1e-9 edge");
  // The step inside is then the rounding floor (64 ulp of the coordinates, 1.4e-14), so
  // the one-sided gradient carries a rounding error of about 1e-2 (an O(1) error would
  // be a wrong gradient).
  for (Coordinates c : {Coordinates::wachspress, Coordinates::discrete_harmonic})
    check_gradients(c, short_edge, 5e-2);
}

}  // namespace
}  // namespace warpfem::mapping
