// Mean value coordinates on polygons whose vertices differ in size by many
// orders of magnitude: every vertex and every point next to it must give finite,
// exact values (no recursion, no tolerance tied to the whole polygon's size).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mapping/barycentric_coordinates.hpp"
#include "mapping/mean_value_coordinates.hpp"

namespace warpfem::mapping {
namespace {

/// A unit square with one vertex pulled to y = −far (a long spike).
PolygonArrays spiked_square(Real far) {
  return PolygonArrays(std::vector<Point<2>>{{0, 0}, {0.5, -far}, {1, 0}, {1, 1}, {0, 1}});
}

/// Σ φ_i = 1, Σ φ_i v_i = x and Σ ∇φ_i = 0, Σ v_i ⊗ ∇φ_i = I (linear precision).
void expect_linear_precision(const PolygonArrays& P, Real x, Real y, const std::vector<Real>& phi,
                             const std::vector<Real>& dx, const std::vector<Real>& dy, Real tol) {
  const Index n = P.size();
  Real s = 0, sx = 0, sy = 0, gx = 0, gy = 0, xx = 0, xy = 0, yx = 0, yy = 0, gmax = 1;
  for (Index i = 0; i < n; ++i) {
    ASSERT_TRUE(std::isfinite(phi[i]) && std::isfinite(dx[i]) && std::isfinite(dy[i])) << "vertex " << i;
    s += phi[i];
    sx += phi[i] * P.x[i];
    sy += phi[i] * P.y[i];
    gx += dx[i];
    gy += dy[i];
    xx += P.x[i] * dx[i];
    xy += P.x[i] * dy[i];
    yx += P.y[i] * dx[i];
    yy += P.y[i] * dy[i];
    gmax = std::max({gmax, std::abs(dx[i] * P.scale), std::abs(dy[i] * P.scale)});
  }
  EXPECT_NEAR(s, 1, tol);
  EXPECT_NEAR(sx, x, tol * P.scale);
  EXPECT_NEAR(sy, y, tol * P.scale);
  // gradients carry 1/length: compare in units of the gradient size
  EXPECT_NEAR(gx * P.scale / gmax, 0, tol);
  EXPECT_NEAR(gy * P.scale / gmax, 0, tol);
  EXPECT_NEAR(xx, 1, tol * gmax);
  EXPECT_NEAR(xy, 0, tol * gmax);
  EXPECT_NEAR(yx, 0, tol * gmax);
  EXPECT_NEAR(yy, 1, tol * gmax);
}

TEST(MeanValueScale, VerticesOfASpikedPolygonGiveKroneckerValuesAndFiniteGradients) {
  for (const Real far : {1.0, 1e4, 1e8, 1e12}) {
    const PolygonArrays P = spiked_square(far);
    const Index n = P.size();
    std::vector<Real> phi(n), dx(n), dy(n), work;
    for (Index j = 0; j < n; ++j) {
      mean_value_coordinates_at(P, P.x[j], P.y[j], phi.data(), dx.data(), dy.data(), work);
      for (Index i = 0; i < n; ++i) EXPECT_EQ(phi[i], i == j ? 1.0 : 0.0) << "far " << far << " vertex " << j;
      for (Index i = 0; i < n; ++i)
        ASSERT_TRUE(std::isfinite(dx[i]) && std::isfinite(dy[i])) << "far " << far << " vertex " << j;
    }
  }
}

TEST(MeanValueScale, PointsNextToTheSmallVerticesKeepLinearPrecision) {
  // Near (0, 0) of a polygon 1e8 long: the distances 1e-9 … 1e-3 are tiny next to
  // the polygon but large next to the vertex's own edges (length 1).
  const PolygonArrays P = spiked_square(1e8);
  const Index n = P.size();
  std::vector<Real> phi(n), dx(n), dy(n), work;
  for (const Real d : {1e-9, 1e-6, 1e-3}) {
    const Real x = 0.5 * d, y = 0.7 * d;  // inside, next to vertex 0
    mean_value_coordinates_at(P, x, y, phi.data(), dx.data(), dy.data(), work);
    EXPECT_LT(phi[0], 1) << "d " << d << ": the point is not the vertex";
    expect_linear_precision(P, x, y, phi, dx, dy, 1e-9);
  }
}

TEST(MeanValueScale, BatchedEvaluationOfASpikedPolygonIsFinite) {
  const std::vector<Point<2>> v{{0, 0}, {0.5, -1e8}, {1, 0}, {1, 1}, {0, 1}};
  Points<2> x(v.size() + 2, 2);
  for (std::size_t i = 0; i < v.size(); ++i) x.row(static_cast<Index>(i)) = v[i].transpose();
  x.row(static_cast<Index>(v.size())) << 0.5, 0.5;
  x.row(static_cast<Index>(v.size()) + 1) << 0.5, -1e7;
  MatrixX phi, dx, dy;
  mean_value_coordinates(PolygonArrays(v), x, phi, dx, dy);
  EXPECT_TRUE(phi.allFinite());
  EXPECT_TRUE(dx.allFinite());
  EXPECT_TRUE(dy.allFinite());
  for (Index p = 0; p < x.rows(); ++p) EXPECT_NEAR(phi.row(p).sum(), 1, 1e-12);
}

}  // namespace
}  // namespace warpfem::mapping
