// The batched kernel of polyhedron mean value coordinates: its edge schedule
// (each edge computed before the triangles that use it, in a slot no other edge
// takes while it is needed) and its agreement with the robust single-point
// formula at random points, next to vertices, edges and faces, and in calls
// whose length is not a multiple of the kernel's block.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "mapping/polyhedron_mean_value_coordinates.hpp"
#include "test_polyhedra.hpp"

namespace warpfem::mapping {
namespace {

std::vector<Polyhedron> cages() {
  return {test::unit_cube(), test::bumpy_sphere(), test::bumpy_sphere(16, 12, 0.2), test::subdivided_cube(3)};
}

TEST(PolyhedronMeanValueKernel, EdgeScheduleComputesEachEdgeBeforeItsTrianglesAndKeepsItsSlot) {
  for (const Polyhedron& P : cages()) {
    const PolyhedronArrays A(P);
    const int m = static_cast<int>(A.triangle_count()), ne = static_cast<int>(A.edge_a.size());
    ASSERT_EQ(static_cast<int>(A.order.size()), m);
    std::vector<int> visits(static_cast<std::size_t>(m)), computed(static_cast<std::size_t>(ne)),
        uses(static_cast<std::size_t>(ne));
    for (const int t : A.order) ++visits[static_cast<std::size_t>(t)];
    for (int t = 0; t < m; ++t) {
      ASSERT_EQ(visits[static_cast<std::size_t>(t)], 1) << "triangle " << t;
      for (int k = 0; k < 3; ++k) ++uses[static_cast<std::size_t>(A.triangle_edges[3 * t + k])];
    }
    ASSERT_EQ(static_cast<int>(A.edge_first.size()), m + 1);
    std::vector<int> holder(static_cast<std::size_t>(A.slot_count), -1);  // the edge each slot holds
    for (int i = 0; i < m; ++i) {
      for (int j = A.edge_first[i]; j < A.edge_first[i + 1]; ++j) {
        const int e = A.scheduled_edges[static_cast<std::size_t>(j)],
                  slot = A.edge_slot[static_cast<std::size_t>(e)];
        ASSERT_TRUE(slot >= 0 && slot < A.slot_count) << "edge " << e;
        ASSERT_EQ(holder[static_cast<std::size_t>(slot)], -1) << "edge " << e << " overwrites a slot in use";
        holder[static_cast<std::size_t>(slot)] = e;
        ++computed[static_cast<std::size_t>(e)];
      }
      const int t = A.order[static_cast<std::size_t>(i)];
      for (int k = 0; k < 3; ++k) {
        const int e = A.triangle_edges[3 * t + k], slot = A.edge_slot[static_cast<std::size_t>(e)];
        ASSERT_EQ(holder[static_cast<std::size_t>(slot)], e) << "triangle " << t << " reads edge " << e;
        if (--uses[static_cast<std::size_t>(e)] == 0) holder[static_cast<std::size_t>(slot)] = -1;
      }
    }
    for (int e = 0; e < ne; ++e) EXPECT_EQ(computed[static_cast<std::size_t>(e)], 1) << "edge " << e;
    // Only the edges open along the front of the visit take a slot: about the
    // square root of the edge count, not the edge count.
    EXPECT_LE(A.slot_count, 4 * std::sqrt(ne) + 4) << ne << " edges";
  }
}

constexpr std::size_t test_random_points = 101;

/// Points inside P: random ones, then at relative distances 1e-2, 1e-4, 1e-7
/// inside every face centroid, every edge midpoint (along each face's normal),
/// and every vertex (along the sum of its faces' normals), in threes.
Points<3> test_points(const Polyhedron& P, unsigned seed) {
  std::vector<Point<3>> x;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> u(0, 1);
  const Point<3> lo = P.bbox_min(), hi = P.bbox_max();
  while (x.size() < test_random_points) {
    const Point<3> q = lo + (hi - lo).cwiseProduct(Point<3>(u(rng), u(rng), u(rng)));
    if (test::winding_number(P, q) > 0.5) x.push_back(q);
  }
  const Real size = (hi - lo).norm();
  std::vector<Point<3>> vertex_normal(static_cast<std::size_t>(P.vertex_count()), Point<3>::Zero());
  for (const auto& t : P.triangles()) {
    const Point<3> a = P.vertex(t[0]), b = P.vertex(t[1]), c = P.vertex(t[2]);
    const Point<3> nu = (b - a).cross(c - a).normalized();
    for (const Real d : {1e-2, 1e-4, 1e-7}) x.push_back((a + b + c) / 3 - d * size * nu);
    for (const Real d : {1e-2, 1e-4, 1e-7}) x.push_back(0.5 * (a + b) - d * size * nu);
    for (int k = 0; k < 3; ++k) vertex_normal[static_cast<std::size_t>(t[k])] += nu;
  }
  for (Index i = 0; i < P.vertex_count(); ++i)
    for (const Real d : {1e-2, 1e-4, 1e-7})
      x.push_back(P.vertex(i) - d * size * vertex_normal[static_cast<std::size_t>(i)].normalized());
  Points<3> out(static_cast<Index>(x.size()), 3);
  for (std::size_t p = 0; p < x.size(); ++p) out.row(static_cast<Index>(p)) = x[p].transpose();
  return out;
}

TEST(PolyhedronMeanValueKernel, CallsOfAnyLengthAgreeWithOneCallTheRobustValuesAndCentralDifferences) {
  for (const Polyhedron& P : {test::unit_cube(), test::bumpy_sphere(), test::subdivided_cube(3)}) {
    const PolyhedronArrays A(P);
    const Index n = A.size();
    const Points<3> x = test_points(P, 3);
    MatrixX phi, dx, dy, dz;
    mean_value_coordinates(A, x, phi, dx, dy, dz);
    // The same points in calls of 1, 15, 17 and 33 points (partial blocks): the same results.
    Real worst_split = 0;
    for (const Index chunk : {Index{1}, Index{15}, Index{17}, Index{33}})
      for (Index p0 = 0; p0 < x.rows(); p0 += chunk) {
        const Index cnt = std::min(chunk, x.rows() - p0);
        MatrixX f, gx, gy, gz;
        mean_value_coordinates(A, Points<3>(x.middleRows(p0, cnt)), f, gx, gy, gz);
        worst_split = std::max({worst_split, (f - phi.middleRows(p0, cnt)).cwiseAbs().maxCoeff(),
                                (gx - dx.middleRows(p0, cnt)).cwiseAbs().maxCoeff(),
                                (gy - dy.middleRows(p0, cnt)).cwiseAbs().maxCoeff(),
                                (gz - dz.middleRows(p0, cnt)).cwiseAbs().maxCoeff()});
      }
    EXPECT_EQ(worst_split, 0) << P.triangle_count() << " triangles";
    // Values against the robust single-point formula, everywhere.
    Real worst_value = 0;
    std::vector<Real> r(static_cast<std::size_t>(n));
    for (Index p = 0; p < x.rows(); ++p) {
      mean_value_coordinates_at(A, x.row(p).transpose(), r.data(), nullptr, nullptr, nullptr);
      for (Index i = 0; i < n; ++i)
        worst_value = std::max(worst_value, std::abs(phi(p, i) - r[static_cast<std::size_t>(i)]));
    }
    EXPECT_LT(worst_value, 1e-12) << P.triangle_count() << " triangles";
    // Gradients against central differences of the values, at the random points
    // and those 1e-2 (relative) inside vertices, edges and faces.
    const Real h = 1e-6 * (P.bbox_max() - P.bbox_min()).norm();
    Real worst_gradient = 0;
    for (Index p = 0; p < x.rows(); ++p) {
      if (p >= static_cast<Index>(test_random_points) &&
          (p - static_cast<Index>(test_random_points)) % 3 != 0)
        continue;  // closer ones
      Points<3> q(6, 3);
      for (int c = 0; c < 3; ++c) {
        q.row(2 * c) = q.row(2 * c + 1) = x.row(p);
        q(2 * c, c) += h, q(2 * c + 1, c) -= h;
      }
      MatrixX f;
      mean_value_coordinates(A, q, f);
      Real g = 1;
      for (Index i = 0; i < n; ++i)
        g = std::max({g, std::abs(dx(p, i)), std::abs(dy(p, i)), std::abs(dz(p, i))});
      for (Index i = 0; i < n; ++i) {
        const Real fd[3] = {(f(0, i) - f(1, i)) / (2 * h), (f(2, i) - f(3, i)) / (2 * h),
                            (f(4, i) - f(5, i)) / (2 * h)};
        worst_gradient = std::max({worst_gradient, std::abs(fd[0] - dx(p, i)) / g,
                                   std::abs(fd[1] - dy(p, i)) / g, std::abs(fd[2] - dz(p, i)) / g});
      }
    }
    std::printf(
        "%lld triangles, %lld points: max |phi - robust| %.1e, max |grad - central differences| / |grad| "
        "%.1e\n",
        static_cast<long long>(P.triangle_count()), static_cast<long long>(x.rows()), worst_value,
        worst_gradient);
    EXPECT_LT(worst_gradient, 1e-6) << P.triangle_count() << " triangles";
  }
}

}  // namespace
}  // namespace warpfem::mapping
