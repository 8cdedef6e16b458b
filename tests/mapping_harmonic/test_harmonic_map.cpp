// Harmonic maps φ: Ω → Λ by fem, bem and mfs (thesis §5.1): boundary data,
// linear precision, convergence of the boundary error, harmonicity, Jacobians.

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cstdio>

#include "core/error.hpp"
#include "harmonic_test_utils.hpp"
#include "mapping/harmonic/bem_harmonic_map.hpp"
#include "mapping/harmonic/fem_harmonic_map.hpp"
#include "mapping/harmonic/intermediate_polygon.hpp"
#include "mapping/harmonic/mfs_harmonic_map.hpp"
#include "mapping/polygon_sampling.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

HarmonicOptions with(HarmonicMethod m, Index nodes = 256) {
  HarmonicOptions o;
  o.method = m;
  o.boundary_nodes = nodes;
  return o;
}

/// An affine image of `P` (a harmonic map whose exact solution is that affine map).
Polygon affine_image(const Polygon& P) {
  Matrix<2> A;
  A << 1.3, 0.4, -0.2, 0.9;
  std::vector<Point<2>> v;
  for (const auto& p : P.vertices()) v.push_back(A * p + Point<2>(0.5, -1));
  return Polygon(v, "affine image");
}

Real affine_error(const HarmonicMap& phi, const Polygon& P, const Polygon& image, const Points<2>& x) {
  Points<2> y;
  phi.eval(x, y);
  // the exact map: the affine map sending P's first three vertices to image's
  Matrix<2> E, F;
  E << P.vertex(1) - P.vertex(0), P.vertex(2) - P.vertex(0);
  F << image.vertex(1) - image.vertex(0), image.vertex(2) - image.vertex(0);
  const Matrix<2> A = F * E.inverse();
  Real worst = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    const Point<2> exact = image.vertex(0) + A * (x.row(p).transpose() - P.vertex(0));
    worst = std::max(worst, (y.row(p).transpose() - exact).norm());
  }
  return worst;
}

TEST(FemHarmonicMap, ReproducesBoundaryDataAtBoundaryNodes) {
  const Polygon P = test::star();
  std::vector<EdgeSpeed> speeds(10, EdgeSpeed::linear);
  speeds[1] = EdgeSpeed::quadratic;
  speeds[6] = EdgeSpeed::quadratic_reversed;
  const FemHarmonicMap phi(P, regular_polygon(10), speeds, 0.05);
  const warpfem::Mesh<2>& m = phi.mesh();
  const auto at = boundary_points(m, P);
  Index boundary = 0;
  Real worst = 0;
  Point<2> y;
  for (Index v = 0; v < m.num_vertices(); ++v) {
    if (!at[static_cast<std::size_t>(v)]) continue;
    ++boundary;
    const Point<2> g = boundary_value(phi.image(), speeds, *at[static_cast<std::size_t>(v)]);
    worst = std::max(worst, (phi.vertex_images().row(v).transpose() - g).norm());
    phi.eval_point(m.vertices.row(v).transpose(), y, nullptr);
    worst = std::max(worst, (y - g).norm());
  }
  EXPECT_GT(boundary, 10 * 5);
  EXPECT_LT(worst, 1e-14);
  // polygon vertices go to Λ's vertices
  for (Index i = 0; i < P.size(); ++i) {
    phi.eval_point(P.vertex(i), y, nullptr);
    EXPECT_LT((y - phi.image().vertex(i)).norm(), 1e-14) << "vertex " << i;
  }
}

TEST(HarmonicMap, LinearPrecisionOnAConcavePolygon) {
  const Polygon P = test::star(), image = affine_image(P);
  const Points<2> x = grid_sample(P, 20);
  // (the solvers themselves; make_harmonic would refuse the concave image)
  EXPECT_LT(affine_error(FemHarmonicMap(P, image, {}, 0.05), P, image, x), 1e-10);
  EXPECT_LT(affine_error(MfsHarmonicMap(P, image, {}, with(HarmonicMethod::mfs, 80)), P, image, x), 1e-8);
  // bem: ∂φ/∂n jumps at the reflex corners, where it is continuous hats: converges, not exact
  Real previous = 1e300;
  for (Index m : {40, 160, 640}) {
    const Real e = affine_error(BemHarmonicMap(P, image, {}, with(HarmonicMethod::bem, m)), P, image, x);
    std::printf("[ bem linear precision ] m = %ld: max error %.3e\n", static_cast<long>(m), e);
    EXPECT_LT(e, 0.5 * previous);
    previous = e;
  }
  EXPECT_LT(previous, 1e-3);
}

TEST(HarmonicMap, BoundaryErrorDecreasesWithTheNodeCount) {
  const Polygon P = test::dart(), L = regular_polygon(4);
  for (HarmonicMethod method : {HarmonicMethod::bem, HarmonicMethod::mfs}) {
    Real previous = 1e300;
    for (Index m : {32, 128, 512}) {
      const Real dev = boundary_deviation(*make_harmonic(P, L, {}, with(method, m)));
      std::printf("[ boundary deviation ] %s m = %ld: %.3e\n", to_string(method).c_str(),
                  static_cast<long>(m), dev);
      EXPECT_LT(dev, 0.8 * previous) << to_string(method) << " m = " << m;
      previous = dev;
    }
    EXPECT_LT(previous, 0.05) << to_string(method);
  }
  EXPECT_LT(boundary_deviation(*make_harmonic(P, L, {}, with(HarmonicMethod::fem))), 1e-5);
}

/// max |Δ_h φ| over x with the nine-point Laplacian (error O(h⁶) on harmonic
/// functions, O(1) elsewhere), and max |∇φ| for scale.
std::pair<Real, Real> discrete_laplacian(const HarmonicMap& phi, const Points<2>& x, Real h) {
  Real worst = 0, scale = 0;
  auto at = [&](const Point<2>& q) {
    Point<2> v;
    phi.eval_point(q, v, nullptr);
    return v;
  };
  for (Index p = 0; p < x.rows(); ++p) {
    const Point<2> q = x.row(p).transpose();
    const Point<2> ex(h, 0), ey(0, h);
    const Point<2> edges = at(q + ex) + at(q - ex) + at(q + ey) + at(q - ey);
    const Point<2> corners = at(q + ex + ey) + at(q + ex - ey) + at(q - ex + ey) + at(q - ex - ey);
    worst = std::max(worst, ((4 * edges + corners - 20 * at(q)) / (6 * h * h)).norm());
    scale = std::max(scale, ((at(q + ex) - at(q - ex)) / (2 * h)).norm());
  }
  return {worst, scale};
}

TEST(HarmonicMap, SmoothApproximationsAreHarmonic) {
  const Polygon P = test::dart(), L = regular_polygon(4);
  const Points<2> x = test::keep_away_from_boundary(grid_sample(P, 32), P, 0.08);
  ASSERT_GT(x.rows(), 10);
  const Real h = 5e-3;
  for (HarmonicMethod method : {HarmonicMethod::bem, HarmonicMethod::mfs}) {
    const auto [lap, grad] = discrete_laplacian(*make_harmonic(P, L, {}, with(method, 200)), x, h);
    std::printf("[ harmonic ] %s: max |Δ_h φ| = %.2e (max |∇φ| %.2f)\n", to_string(method).c_str(), lap,
                grad);
    EXPECT_LT(lap, 1e-4 * grad) << to_string(method);
  }
  // the same measure sees the kinks of the piecewise-linear fem solution
  const auto [lap, grad] = discrete_laplacian(*make_harmonic(P, L, {}, with(HarmonicMethod::fem)), x, h);
  EXPECT_GT(lap, 10 * grad);
}

TEST(HarmonicMap, JacobiansMatchCentralDifferences) {
  const Polygon P = test::dart(), L = regular_polygon(4);
  const Points<2> x = test::keep_away_from_boundary(grid_sample(P, 10), P, 0.02);
  for (HarmonicMethod method : {HarmonicMethod::bem, HarmonicMethod::mfs})
    EXPECT_LT(test::jacobian_fd_error(*make_harmonic(P, L, {}, with(method, 128)), x, 1e-6), 1e-6)
        << to_string(method);
}

TEST(HarmonicMap, WithImageEqualsANewSolve) {
  const Polygon P = test::star(), L1 = regular_polygon(10),
                L2 = cyclic_intermediate(test::star(), test::star(0.5));
  const Points<2> x = grid_sample(P, 10);
  for (HarmonicMethod method : {HarmonicMethod::fem, HarmonicMethod::bem, HarmonicMethod::mfs}) {
    Points<2> a, b;
    make_harmonic(P, L1, {}, with(method, 100))->with_image(L2)->eval(x, a);
    make_harmonic(P, L2, {}, with(method, 100))->eval(x, b);
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-12) << to_string(method);
  }
}

TEST(HarmonicMap, RejectsANonConvexImage) {
  try {
    make_harmonic(test::diamond(), test::dart(), {}, with(HarmonicMethod::fem));
    FAIL() << "expected warpfem::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not convex"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_harmonic(test::diamond(), regular_polygon(5)), Error);
  EXPECT_THROW(parse_harmonic_method("fdm"), Error);
}

}  // namespace
}  // namespace warpfem::mapping
