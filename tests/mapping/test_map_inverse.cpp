// Newton inverses of maps: the tolerance follows the size of the data, and the
// report names the worst point, so a failed inverse is never taken for f⁻¹.

#include <gtest/gtest.h>

#include <cmath>

#include "mapping/barycentric_map.hpp"
#include "mapping/map_inverse.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

Polygon scaled(const Polygon& P, Real s, const std::string& name) {
  std::vector<Point<2>> v;
  for (const Point<2>& p : P.vertices()) v.push_back(s * p);
  return test::polygon(v, name);
}

TEST(MapInverse, ToleranceIsRelativeToTheSizeOfTheData) {
  // The same map at the scales 1e-8, 1 and 1e8 must be inverted equally well
  // relative to its size (an absolute floor would stop at once on the small one).
  for (const Real s : {1e-8, 1.0, 1e8}) {
    const Polygon from = scaled(test::convex6(), s, "hexagon"), to = scaled(test::convex6(), s, "hexagon");
    std::vector<Point<2>> bent = to.vertices();
    bent[2] = s * Point<2>(2.8, 1.1);
    const BarycentricMap f(from, test::polygon(bent, "bent hexagon"));
    Points<2> x0(3, 2), y, x;
    x0 << 1.0, 1.0, 2.0, 0.5, 0.5, 1.5;
    x0 *= s;
    f.eval(x0, y);
    x = y;  // a poor guess: the target points themselves
    const InverseReport r = invert<2>(f, y, x);
    EXPECT_EQ(r.converged, 3) << "scale " << s;
    EXPECT_LE(r.max_residual, 1e-12 * 3 * s) << "scale " << s;
    EXPECT_LE((x - x0).cwiseAbs().maxCoeff(), 1e-10 * s) << "scale " << s;
  }
}

TEST(MapInverse, PointsWithoutPreimageAreReportedNotConverged) {
  const BarycentricMap f(test::convex6(), test::convex6());  // the identity on the hexagon
  Points<2> y(3, 2), x;
  y << 1.0, 1.0, 1.5, 1.5, std::nan(""), 0.0;
  x = y;
  const InverseReport r = invert<2>(f, y, x);
  EXPECT_EQ(r.converged, 2);
  EXPECT_EQ(r.worst, 2);
  EXPECT_TRUE(std::isnan(r.max_residual));
}

}  // namespace
}  // namespace warpfem::mapping
