// Triangles over a polygon's own vertices: they cover it exactly (areas add up),
// are all counter-clockwise, and a polygon that is not simple or not
// counter-clockwise gets none.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/mesh/polygon_triangulation.hpp"

using namespace warpfem;

namespace {

double signed_area(const Point<2>& a, const Point<2>& b, const Point<2>& c) {
  return 0.5 * ((b(0) - a(0)) * (c(1) - a(1)) - (b(1) - a(1)) * (c(0) - a(0)));
}

double polygon_area(const std::vector<Point<2>>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point<2>& u = p[i];
    const Point<2>& v = p[(i + 1) % p.size()];
    a += 0.5 * (u(0) * v(1) - v(0) * u(1));
  }
  return a;
}

}  // namespace

TEST(PolygonTriangulation, ANonConvexRingIsCoveredByPositiveTrianglesOfItsVertices) {
  // A hairpin-like ring of eight vertices (the boundary nodes of a strongly
  // bent output cell), with collinear runs.
  const std::vector<Point<2>> ring = {{0, 0},     {1, 0},   {2, 0},   {2, 0.5},
                                      {0.5, 0.5}, {0.5, 1}, {2, 1.2}, {0, 1.5}};
  const auto triangles = triangulate_simple_polygon(ring);
  ASSERT_EQ(triangles.size(), ring.size() - 2);
  double area = 0;
  for (const auto& t : triangles) {
    const double a = signed_area(ring[static_cast<std::size_t>(t[0])], ring[static_cast<std::size_t>(t[1])],
                                 ring[static_cast<std::size_t>(t[2])]);
    EXPECT_GT(a, 0);
    area += a;
  }
  EXPECT_NEAR(area, polygon_area(ring), 1e-14);
}

TEST(PolygonTriangulation, CrossingOrClockwiseRingsGetNoTriangles) {
  const std::vector<Point<2>> bow_tie = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  EXPECT_TRUE(triangulate_simple_polygon(bow_tie).empty());
  const std::vector<Point<2>> clockwise = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  EXPECT_TRUE(triangulate_simple_polygon(clockwise).empty());
  const std::vector<Point<2>> counter_clockwise(clockwise.rbegin(), clockwise.rend());
  EXPECT_EQ(triangulate_simple_polygon(counter_clockwise).size(), 2u);
}
