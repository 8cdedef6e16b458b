// Vertex paths between polyhedra: both paths reproduce the cages at t = 0 and 1 bit for
// bit; under a rotation the linear path crushes the cage half-way while the intrinsic
// path keeps it congruent; the intrinsic path commutes with similarity transformations;
// on a large twist it keeps every triangle's area within bounds and needs fewer
// composite steps; make_map takes "vertex_path" for polyhedra and names it on failure.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <numbers>

#include "core/error.hpp"
#include "mapping/make_map.hpp"
#include "mapping/polyhedron_composite_map.hpp"
#include "mapping/polyhedron_vertex_path.hpp"
#include "test_polyhedra.hpp"

namespace warpfem::mapping {
namespace {

Real max_distance(const std::vector<Point<3>>& a, const std::vector<Point<3>>& b) {
  Real d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
  return d;
}

std::vector<Real> triangle_areas(const std::vector<Point<3>>& v,
                                 const std::vector<Polyhedron::Triangle>& tris) {
  std::vector<Real> area;
  for (const auto& t : tris)
    area.push_back(0.5 * (v[static_cast<std::size_t>(t[1])] - v[static_cast<std::size_t>(t[0])])
                             .cross(v[static_cast<std::size_t>(t[2])] - v[static_cast<std::size_t>(t[0])])
                             .norm());
  return area;
}

Polyhedron transformed(const Polyhedron& P, const Matrix<3>& A, const Point<3>& b, const std::string& name) {
  std::vector<Point<3>> v;
  for (const auto& p : P.vertices()) v.push_back(A * p + b);
  return Polyhedron::checked(v, P.triangles(), name);
}

/// The least ratio, over t = k/16 and all triangles, of a triangle's area on the path
/// to the smaller of its areas in source and target.
Real least_area_ratio(const PolyhedronVertexPath& path) {
  const auto a0 = triangle_areas(path.source(), path.triangles());
  const auto a1 = triangle_areas(path.target(), path.triangles());
  Real least = 1e300;
  for (int k = 1; k < 16; ++k) {
    const auto a = triangle_areas(path.vertices_at(k / 16.0), path.triangles());
    for (std::size_t i = 0; i < a.size(); ++i) least = std::min(least, a[i] / std::min(a0[i], a1[i]));
  }
  return least;
}

TEST(PolyhedronVertexPath, ReproducesBothCagesExactlyAndIsContinuousThere) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Polyhedron target = test::twisted(cube, 0.75 * std::numbers::pi);
  for (const VertexPathType type : {VertexPathType::linear, VertexPathType::intrinsic}) {
    SCOPED_TRACE(to_string(type));
    const PolyhedronVertexPath path(cube, target, type);
    EXPECT_EQ(max_distance(path.vertices_at(0), cube.vertices()), 0.0);
    EXPECT_EQ(max_distance(path.vertices_at(1), target.vertices()), 0.0);
    EXPECT_LT(max_distance(path.vertices_at(1e-9), cube.vertices()), 1e-7);
    EXPECT_LT(max_distance(path.vertices_at(1 - 1e-9), target.vertices()), 1e-7);
    const PolyhedronVertexPath back = path.reversed();
    EXPECT_EQ(max_distance(back.vertices_at(0), target.vertices()), 0.0);
    EXPECT_EQ(max_distance(back.vertices_at(1), cube.vertices()), 0.0);
    EXPECT_EQ(max_distance(back.vertices_at(0.25), path.vertices_at(0.75)), 0.0);
  }
}

TEST(PolyhedronVertexPath, RotationCrushesTheLinearPathButTheIntrinsicOneStaysCongruent) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Matrix<3> Q =
      Eigen::AngleAxis<Real>(150 * std::numbers::pi / 180, Point<3>(1, 2, 3).normalized()).toRotationMatrix();
  const Polyhedron target = transformed(cube, Q, Point<3>(2, -1, 0.5), "rotated cube");
  const Real V0 = cube.signed_volume();
  const PolyhedronVertexPath linear(cube, target, VertexPathType::linear);
  const Polyhedron half(linear.vertices_at(0.5), cube.triangles(), "linear half-way");
  // (I + Q) / 2 scales volumes by cos²(75°) ≈ 0.067.
  EXPECT_LT(half.signed_volume(), 0.1 * V0);

  const PolyhedronVertexPath intrinsic(cube, target, VertexPathType::intrinsic);
  const auto a0 = triangle_areas(cube.vertices(), cube.triangles());
  for (int k = 1; k < 10; ++k) {
    const Real t = k / 10.0;
    const auto v = intrinsic.vertices_at(t);
    const Polyhedron cage(v, cube.triangles(), "intrinsic cage");
    EXPECT_NEAR(cage.signed_volume() / V0, 1, 1e-9) << "t = " << t;
    const auto a = triangle_areas(v, cube.triangles());
    for (std::size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i] / a0[i], 1, 1e-9) << "t = " << t << ", " << i;
    // Congruent: every vertex distance is kept.
    for (std::size_t i = 0; i < v.size(); i += 7)
      for (std::size_t j = 0; j < v.size(); j += 5)
        ASSERT_NEAR((v[i] - v[j]).norm(),
                    (cube.vertex(static_cast<Index>(i)) - cube.vertex(static_cast<Index>(j))).norm(), 1e-9);
  }
}

TEST(PolyhedronVertexPath, IntrinsicPathCommutesWithSimilarityTransformations) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Polyhedron target = test::twisted(cube, 0.75 * std::numbers::pi);
  const Matrix<3> A = 2.5 * Eigen::AngleAxis<Real>(1.1, Point<3>(-1, 0.5, 2).normalized()).toRotationMatrix();
  const Point<3> b(10, -3, 7);
  const PolyhedronVertexPath path(cube, target, VertexPathType::intrinsic);
  const PolyhedronVertexPath moved(transformed(cube, A, b, "moved cube"),
                                   transformed(target, A, b, "moved target"), VertexPathType::intrinsic);
  for (const Real t : {0.2, 0.5, 0.9}) {
    auto v = path.vertices_at(t);
    for (auto& p : v) p = A * p + b;
    EXPECT_LT(max_distance(moved.vertices_at(t), v), 1e-11) << "t = " << t;
  }
  // The paths differ by far more than that tolerance.
  const PolyhedronVertexPath linear(cube, target, VertexPathType::linear);
  EXPECT_GT(max_distance(linear.vertices_at(0.5), path.vertices_at(0.5)), 0.05);
}

TEST(PolyhedronVertexPath, LargeTwistKeepsTrianglesAndNeedsFewerSteps) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Polyhedron target = test::twisted(cube, 0.75 * std::numbers::pi);
  const PolyhedronVertexPath linear(cube, target, VertexPathType::linear);
  const PolyhedronVertexPath intrinsic(cube, target, VertexPathType::intrinsic);
  const Real linear_least = least_area_ratio(linear), intrinsic_least = least_area_ratio(intrinsic);
  const PolyhedronCompositeMap f_linear = build_polyhedron_composite(cube, target);
  const PolyhedronCompositeMap f_intrinsic =
      build_polyhedron_composite(cube, target, {.vertex_path = VertexPathType::intrinsic});
  std::printf("135 degree twist: least triangle area ratio linear %.3g, intrinsic %.3g; %s; %s\n",
              linear_least, intrinsic_least, f_linear.describe().c_str(), f_intrinsic.describe().c_str());
  // The top's triangles turn by 135°: the linear path shrinks them by cos²(67.5°) ≈ 0.15.
  EXPECT_LT(linear_least, 0.3);
  EXPECT_GT(intrinsic_least, 0.5);
  EXPECT_LT(f_intrinsic.steps(), f_linear.steps());
}

TEST(PolyhedronVertexPath, MakeMapTakesTheFieldAndNamesItWhenTheCageDegenerates) {
  const Polyhedron cube = test::subdivided_cube(3);
  PolyhedronMapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = cube;
  spec.target = test::twisted(cube, std::numbers::pi);
  spec.origin = "half_turn.json";
  try {
    make_map(spec);
    ADD_FAILURE() << "the linear path through a crushed cage was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().key_path, "map.vertex_path") << e.what();
    EXPECT_NE(std::string(e.what()).find("\"intrinsic\""), std::string::npos) << e.what();
  }
  spec.vertex_path = "spline";
  try {
    make_map(spec);
    ADD_FAILURE() << "an unknown vertex path was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().key_path, "map.vertex_path") << e.what();
  }
  spec.vertex_path = "intrinsic";
  PolyhedronMapCheck check;
  const MapPtr<3> f = make_map(spec, &check);
  EXPECT_NE(f->describe().find("intrinsic vertex path"), std::string::npos) << f->describe();
  EXPECT_TRUE(check.passed());
}

}  // namespace
}  // namespace warpfem::mapping
