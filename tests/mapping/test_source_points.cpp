// Points on the source polygon as users give them: computed on an edge in
// floating point they may lie a rounding error outside; within 1e-12 of the
// diameter they are boundary points, farther out they are refused all at once.

#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "mapping/make_map.hpp"
#include "mapping/source_points.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

/// 200 points (1 − t) a + t b on every edge, t = k / 199, computed in double.
Points<2> points_on_edges(const Polygon& P) {
  Points<2> x(200 * P.size(), 2);
  for (Index i = 0; i < P.size(); ++i)
    for (int k = 0; k < 200; ++k) {
      const Real t = k / 199.0;
      x.row(200 * i + k) = ((1 - t) * P.vertex(i) + t * P.vertex(i + 1)).transpose();
    }
  return x;
}

TEST(SourcePoints, PointsComputedOnEdgesAreAllAcceptedAndMapped) {
  for (const Polygon& P : {test::diamond(), test::star(), test::concave32(), test::convex6()}) {
    Points<2> x = points_on_edges(P);
    Index outside = 0;
    for (Index p = 0; p < x.rows(); ++p) outside += P.side_of(x.row(p).transpose()) < 0;
    const Points<2> original = x;
    SourcePointsReport report;
    ASSERT_NO_THROW(report = accept_source_points(P, x, "edges.csv")) << P.name();
    std::printf("[ %s ] %ld of %ld edge points outside in floating point, %ld moved onto the boundary\n",
                P.name().c_str(), static_cast<long>(outside), static_cast<long>(x.rows()),
                static_cast<long>(report.snapped));
    EXPECT_EQ(report.snapped, outside) << P.name();
    EXPECT_LE((x - original).rowwise().norm().maxCoeff(), 1e-12 * (P.bbox_max() - P.bbox_min()).norm());
  }
}

TEST(SourcePoints, EdgePointsOfTheDartMapThroughACheckedMap) {
  MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = test::diamond();
  spec.target = test::dart();
  const MapPtr<2> f = make_map(spec);
  Points<2> x = points_on_edges(*spec.source), y;
  accept_source_points(*spec.source, x, "edges.csv");
  f->eval(x, y);
  EXPECT_TRUE(y.allFinite());
  // the edge from vertex 0 to 1 is the same in source and target (a linear map along edges)
  for (int k = 0; k < 200; ++k) EXPECT_NEAR((y.row(k) - x.row(k)).norm(), 0, 1e-12) << k;
}

TEST(SourcePoints, FartherPointsAreRefusedTenAtATimeWithTheirDistances) {
  const Polygon P = test::diamond();  // diameter 2√2
  Points<2> x(20, 2);
  for (Index p = 0; p < 20; ++p) x.row(p) << 0.1, 0.1;
  x.row(3) << 1.0 + 1e-9, 0.0;  // 1e-9 outside: far more than 1e-12 · diameter
  for (Index p = 5; p < 19; ++p) x.row(p) << 2.0 + p, 0.0;
  try {
    accept_source_points(P, x, "pts.csv");
    FAIL() << "expected warpfem::Error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.context().file, "pts.csv");
    EXPECT_NE(what.find("point 4 (1.000000001, 0) lies outside the source polygon by 1e-09"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("point 14 (15, 0) lies outside"), std::string::npos) << what;
    EXPECT_EQ(what.find("point 15 "), std::string::npos) << "only ten are listed: " << what;
    EXPECT_NE(what.find("15 of 20 points are outside"), std::string::npos) << what;
  }
}

TEST(SourcePoints, NonFinitePointsAreRefused) {
  Points<2> x(2, 2);
  x << 0, 0, std::nan(""), 0;
  EXPECT_THROW(accept_source_points(test::diamond(), x, "nan.csv"), Error);
}

}  // namespace
}  // namespace warpfem::mapping
