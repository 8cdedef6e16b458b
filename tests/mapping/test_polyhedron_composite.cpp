// Composite mean value maps between polyhedra: affine targets are reproduced
// exactly, a cube → twisted cube map gets an adaptive partition that is fold-free
// on a probe set clustered at the boundary with images inside the target, and
// an impossible request is refused naming the interval and min det J.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <random>

#include "core/error.hpp"
#include "mapping/polyhedron_composite_map.hpp"
#include "test_polyhedra.hpp"

namespace warpfem::mapping {
namespace {

Points<3> probe_points(const Polyhedron& P, Index random_count) {
  const Points<3> clustered = polyhedron_check_sample(P, 4);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<Real> u(0.001, 0.999);
  Points<3> x(clustered.rows() + random_count, 3);
  x.topRows(clustered.rows()) = clustered;
  for (Index p = 0; p < random_count; ++p) x.row(clustered.rows() + p) << u(rng), u(rng), u(rng);
  return x;
}

TEST(PolyhedronCompositeMap, ReproducesAffineTargets) {
  const Polyhedron cube = test::subdivided_cube(2);
  const Matrix<3> A = 1.7 * Eigen::AngleAxis<Real>(0.4, Point<3>(1, -1, 2).normalized()).toRotationMatrix() *
                      Eigen::Vector3d(1, 0.5, 2).asDiagonal();
  const Point<3> b(0.3, -2, 5);
  std::vector<Point<3>> v;
  for (const auto& p : cube.vertices()) v.push_back(A * p + b);
  const Polyhedron target = Polyhedron::checked(v, cube.triangles(), "affine image");
  const PolyhedronCompositeMap f(cube, target, {0, 0.5, 1});
  const Points<3> x0 = probe_points(cube, 200);
  Points<3> x;
  Jacobians<3> J;
  f.eval_with_jacobian(x0, x, J);
  for (Index p = 0; p < x0.rows(); ++p) {
    ASSERT_LT((x.row(p).transpose() - (A * x0.row(p).transpose() + b)).norm(), 1e-12) << p;
    ASSERT_LT((jacobian_at<3>(J, p) - A).norm(), 1e-9) << p;
  }
}

TEST(PolyhedronCompositeMap, TwistedCubeIsFoldFreeWithImagesInside) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Polyhedron target = test::twisted(cube, 0.75 * std::numbers::pi);
  const PolyhedronCompositeMap f = build_polyhedron_composite(cube, target);
  EXPECT_GE(f.steps(), 1);
  const Points<3> x0 = probe_points(cube, 2000);
  Points<3> x;
  Jacobians<3> J;
  f.eval_with_jacobian(x0, x, J);
  Real min_det = 1e300;
  for (Index p = 0; p < x0.rows(); ++p) min_det = std::min(min_det, jacobian_at<3>(J, p).determinant());
  EXPECT_GT(min_det, 0) << f.describe() << " on " << x0.rows() << " probe points";
  std::printf("%s: min det J_f = %.3g on %d probe points\n", f.describe().c_str(), min_det,
              static_cast<int>(x0.rows()));
  for (Index p = 0; p < x.rows(); ++p)
    ASSERT_GT(test::winding_number(target, x.row(p).transpose()), 0.5) << "image of probe point " << p;
  // The images of the cube's vertices are the target's.
  Points<3> corners(cube.vertex_count(), 3);
  for (Index i = 0; i < cube.vertex_count(); ++i) corners.row(i) = cube.vertex(i).transpose();
  f.eval(corners, x);
  for (Index i = 0; i < cube.vertex_count(); ++i)
    EXPECT_LT((x.row(i).transpose() - target.vertex(i)).norm(), 1e-12) << "vertex " << i;
}

TEST(PolyhedronCompositeMap, RefusesNamingIntervalAndMinDet) {
  const Polyhedron cube = test::subdivided_cube(2);
  const Polyhedron target = test::twisted(cube, 0.9 * std::numbers::pi);
  try {
    build_polyhedron_composite(cube, target, {.epsilon = 1e-8, .max_halvings = 0});
    ADD_FAILURE() << "a single step for a 162 degree twist was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    std::printf("%s\n", m.c_str());
    EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;
    EXPECT_NE(m.find("min det J"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace warpfem::mapping

namespace warpfem::mapping {
namespace {

TEST(PolyhedronCompositeMap, LinearPathThroughADegenerateCageIsRefusedNamingTheTime) {
  // A half turn moves opposite top vertices through each other at t = 1/2.
  const Polyhedron cube = test::subdivided_cube(3);
  try {
    build_polyhedron_composite(cube, test::twisted(cube, std::numbers::pi));
    ADD_FAILURE() << "a linear vertex path through a degenerate polyhedron was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("intermediate polyhedron at t = 0.5"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace warpfem::mapping

namespace warpfem::mapping {
namespace {

TEST(PolyhedronCompositeMap, NewtonInverseIsTheIdentityAfterTheMap) {
  const Polyhedron cube = test::subdivided_cube(3);
  const Polyhedron target = test::twisted(cube, 0.75 * std::numbers::pi);
  const PolyhedronCompositeMap f = build_polyhedron_composite(cube, target);
  const Points<3> x0 = probe_points(cube, 500);
  Points<3> y, x;
  f.eval(x0, y);
  // The backward map alone is only an approximation of f⁻¹.
  f.backward().eval(y, x);
  const Real backward_error = (x - x0).rowwise().norm().maxCoeff();
  VectorX residual;
  f.inverse(y, x, residual);
  EXPECT_LT(residual.maxCoeff(), 1e-12);
  EXPECT_LT((x - x0).rowwise().norm().maxCoeff(), 1e-10) << "backward map error was " << backward_error;
  EXPECT_GT(backward_error, 1e-6) << "the test should need Newton";
}

}  // namespace
}  // namespace warpfem::mapping
