// Composite mean value maps on polyhedron pairs of different kinds: the unit cube
// onto a non-convex dented cube, onto a cube twisted by 3/8 of a turn, (218
// vertices) onto a rounded, bumpy cube, and with the intrinsic vertex path onto a
// half-turn twist and onto the 3/8-turn twist turned by 144° about a horizontal axis
// (both crush or self-intersect the linear path's cage half-way). Checked without the map's own
// Jacobian: tiny tetrahedra at probe points clustered at every vertex, edge and
// face are mapped and must keep their orientation; images lie inside the target
// (winding number); f(f⁻¹(y)) = y to 1e-10.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "mapping/polyhedron_composite_map.hpp"
#include "test_polyhedra.hpp"

namespace warpfem::mapping {
namespace {

struct Pair {
  std::string name;
  Polyhedron source, target;
  VertexPathType path = VertexPathType::linear;
};

/// The cube with the inner vertices of its top face pushed down by `depth`: not convex.
Polyhedron dented(const Polyhedron& cube, Real depth) {
  std::vector<Point<3>> v;
  for (Point<3> p : cube.vertices()) {
    const bool inner_top =
        p.z() > 1 - 1e-12 && p.x() > 1e-12 && p.x() < 1 - 1e-12 && p.y() > 1e-12 && p.y() < 1 - 1e-12;
    if (inner_top) p.z() -= depth;
    v.push_back(p);
  }
  return Polyhedron::checked(v, cube.triangles(), "dented cube");
}

/// Every vertex moved halfway towards the sphere through the cube's corners, then
/// bumped along the radius: a rounded box with ripples, many vertices.
Polyhedron rounded_bumpy(const Polyhedron& cube) {
  const Point<3> c(0.5, 0.5, 0.5);
  const Real R = std::sqrt(3.0) / 2;
  std::vector<Point<3>> v;
  for (const Point<3>& p : cube.vertices()) {
    const Point<3> d = p - c;
    const Real r = d.norm();
    const Real bump = 1 + 0.04 * std::sin(9 * p.x()) * std::sin(9 * p.y()) * std::sin(9 * p.z());
    v.push_back(c + d * ((0.5 + 0.5 * R / r) * bump));
  }
  return Polyhedron::checked(v, cube.triangles(), "rounded bumpy cube");
}

/// The cage turned by `angle` about the x axis through its centre.
Polyhedron turned(const Polyhedron& P, Real angle) {
  const Matrix<3> Q = Eigen::AngleAxis<Real>(angle, Point<3>::UnitX()).toRotationMatrix();
  const Point<3> c(0.5, 0.5, 0.5);
  std::vector<Point<3>> v;
  for (const Point<3>& p : P.vertices()) v.push_back(c + Q * (p - c));
  return Polyhedron::checked(v, P.triangles(), "turned " + P.name());
}

std::vector<Pair> pairs() {
  const Polyhedron cube3 = test::subdivided_cube(3), cube6 = test::subdivided_cube(6);
  return {
      {"convex onto non-convex", cube3, dented(cube3, 0.45)},
      {"large twist", cube3, test::twisted(cube3, 0.75 * std::numbers::pi)},
      {"many vertices", cube6, rounded_bumpy(cube6)},
      {"half turn, intrinsic path", cube3, test::twisted(cube3, std::numbers::pi), VertexPathType::intrinsic},
      {"twist turned upside down, intrinsic path", cube3,
       turned(test::twisted(cube3, 0.75 * std::numbers::pi), 0.8 * std::numbers::pi),
       VertexPathType::intrinsic}};
}

class PolyhedronPairs : public ::testing::TestWithParam<int> {};

TEST_P(PolyhedronPairs, FoldFreeOnTinyTetrahedraImagesInsideAndInvertible) {
  const Pair pair = pairs()[static_cast<std::size_t>(GetParam())];
  SCOPED_TRACE(pair.name);
  const PolyhedronCompositeMap f =
      build_polyhedron_composite(pair.source, pair.target, {.vertex_path = pair.path});

  // Probe points: clustered at every vertex, edge and face (several offsets), plus random ones.
  const Points<3> clustered = polyhedron_check_sample(pair.source, 6);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> u(1e-3, 1 - 1e-3);
  const Index n = clustered.rows() + 2000;
  Points<3> x0(n, 3);
  x0.topRows(clustered.rows()) = clustered;
  for (Index p = clustered.rows(); p < n; ++p) x0.row(p) << u(rng), u(rng), u(rng);

  // A tiny tetrahedron at each probe: its legs point into the cube (towards its centre).
  const Real h = 1e-6;
  Points<3> corners(4 * n, 3);
  for (Index p = 0; p < n; ++p)
    for (int k = 0; k < 4; ++k) {
      corners.row(4 * p + k) = x0.row(p);
      if (k > 0) corners(4 * p + k, k - 1) += x0(p, k - 1) < 0.5 ? h : -h;
    }
  Points<3> y;
  f.eval(corners, y);
  Index folded = 0;
  Real least = 1e300;
  for (Index p = 0; p < n; ++p) {
    Matrix<3> legs;
    Real orientation = 1;
    for (int k = 0; k < 3; ++k) {
      legs.col(k) = (y.row(4 * p + k + 1) - y.row(4 * p)).transpose() / h;
      orientation *= x0(p, k) < 0.5 ? 1 : -1;
    }
    const Real det = orientation * legs.determinant();
    least = std::min(least, det);
    if (!(det > 0)) ++folded;
  }
  std::printf("%s: %s, %lld probes, least finite-difference det J_f %.3g\n", pair.name.c_str(),
              f.describe().c_str(), static_cast<long long>(n), least);
  EXPECT_EQ(folded, 0) << "of " << n << " probe tetrahedra";

  // Images inside the target.
  Points<3> x;
  f.eval(x0, x);
  Index outside = 0;
  for (Index p = 0; p < n; ++p)
    if (test::winding_number(pair.target, x.row(p).transpose()) < 0.5) ++outside;
  EXPECT_EQ(outside, 0);

  // f⁻¹ ∘ f = id, f ∘ f⁻¹ = id.
  Points<3> back, again;
  VectorX residual;
  f.inverse(x, back, residual);
  f.eval(back, again);
  EXPECT_LT((again - x).rowwise().norm().maxCoeff(), 1e-10);
  // In Ω0 the error is the residual over the smallest singular value of J_f, which the
  // dent's pit brings down to about 1e-4.
  EXPECT_LT((back - x0).rowwise().norm().maxCoeff(), 1e-8);
}

INSTANTIATE_TEST_SUITE_P(Pairs, PolyhedronPairs, ::testing::Values(0, 1, 2, 3, 4));

}  // namespace
}  // namespace warpfem::mapping
