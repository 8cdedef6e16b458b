// Vertex paths: endpoints, linear interpolation, and the intrinsic path's
// similarity invariance (rotations are interpolated as rotations).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>

#include "core/error.hpp"
#include "mapping/vertex_path.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

Polygon rotated(const Polygon& P, Real angle, Real scale = 1, Point<2> shift = Point<2>::Zero()) {
  const Eigen::Rotation2D<Real> R(angle);
  std::vector<Point<2>> v;
  for (const auto& p : P.vertices()) v.push_back(scale * (R * p) + shift);
  return Polygon::checked(v, P.name() + " rotated");
}

Real distance(const std::vector<Point<2>>& a, const std::vector<Point<2>>& b) {
  Real d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
  return d;
}

TEST(VertexPath, ReproducesEndpointsExactly) {
  for (auto type : {VertexPathType::linear, VertexPathType::intrinsic}) {
    const VertexPath path(test::star(), test::star(0.5), type);
    EXPECT_EQ(distance(path.vertices_at(0), test::star().vertices()), 0.0);
    EXPECT_EQ(distance(path.vertices_at(1), test::star(0.5).vertices()), 0.0);
    // and continuously: t → 0 approaches the source
    EXPECT_LT(distance(path.vertices_at(1e-9), test::star().vertices()), 1e-8);
    EXPECT_LT(distance(path.vertices_at(1 - 1e-9), test::star(0.5).vertices()), 1e-8);
  }
}

TEST(VertexPath, LinearIsTheVertexAverage) {
  const VertexPath path(test::diamond(), test::dart(), VertexPathType::linear);
  const auto v = path.vertices_at(0.25);
  EXPECT_LT((v[2] - Point<2>(0.75 * 1 + 0.25 * -0.6, 0)).norm(), 1e-15);
  EXPECT_LT((v[0] - Point<2>(-1, 0)).norm(), 1e-15);
}

TEST(VertexPath, IntrinsicInterpolatesRotationsAsRotations) {
  const Polygon S = test::star();
  const VertexPath intrinsic(S, rotated(S, std::numbers::pi / 2), VertexPathType::intrinsic);
  const VertexPath linear(S, rotated(S, std::numbers::pi / 2), VertexPathType::linear);
  const auto half = rotated(S, std::numbers::pi / 4).vertices();
  EXPECT_LT(distance(intrinsic.vertices_at(0.5), half), 1e-12);
  EXPECT_GT(distance(linear.vertices_at(0.5), half), 0.2);  // linear shrinks the star instead
}

TEST(VertexPath, IntrinsicIsSimilarityInvariantAndCloses) {
  const Polygon A = test::star(), B = test::star(0.5, 0.3);
  const VertexPath p(A, B, VertexPathType::intrinsic);
  const Real angle = 0.7, scale = 2.5;
  const Point<2> shift(3, -1);
  const VertexPath q(rotated(A, angle, scale, shift), rotated(B, angle, scale, shift),
                     VertexPathType::intrinsic);
  for (Real t : {0.2, 0.5, 0.8}) {
    const Polygon Pt = p.polygon_at(t);  // validated: simple and counter-clockwise
    const Polygon Qt = q.polygon_at(t);
    EXPECT_LT(distance(rotated(Pt, angle, scale, shift).vertices(), Qt.vertices()), 1e-12) << "t = " << t;
  }
}

TEST(VertexPath, NamesTheParameterOfAnInvalidIntermediatePolygon) {
  // Rotating a thin bar by 180 degrees with linear paths collapses it at t = 0.5.
  const Polygon bar = test::polygon({{-1, -0.1}, {1, -0.1}, {1, 0.1}, {-1, 0.1}}, "bar");
  const VertexPath path(bar, rotated(bar, std::numbers::pi), VertexPathType::linear);
  try {
    path.polygon_at(0.5);
    FAIL() << "expected warpfem::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t = 0.5"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace warpfem::mapping
