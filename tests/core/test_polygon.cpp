#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/polygon.hpp"

using namespace warpfem;

namespace {
std::vector<Point<2>> square() {
  return {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
}

std::string validation_message(std::vector<Point<2>> v) {
  try {
    Polygon::checked(std::move(v), "test polygon");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Polygon, AcceptsCounterClockwiseSquareWithCollinearVertices) {
  EXPECT_NO_THROW(Polygon::checked(square()));
  // A square carrying extra vertices along its sides is a valid parametrization domain.
  EXPECT_NO_THROW(Polygon::checked({{0, 0}, {0.5, 0}, {1, 0}, {1, 0.5}, {1, 1}, {0.5, 1}, {0, 1}, {0, 0.5}}));
}

TEST(Polygon, RejectsClockwiseOrderWithHint) {
  auto v = square();
  std::reverse(v.begin(), v.end());
  const std::string m = validation_message(v);
  EXPECT_NE(m.find("clockwise"), std::string::npos) << m;
  EXPECT_NE(m.find("reverse the vertex order"), std::string::npos) << m;
}

TEST(Polygon, RejectsSelfIntersectionNamingEdges) {
  // Bow tie: edges 0 and 2 cross.
  const std::string m = validation_message({{0, 0}, {1, 1}, {1, 0}, {0, 1}});
  EXPECT_NE(m.find("not simple"), std::string::npos) << m;
  EXPECT_NE(m.find("edge 0 and edge 2"), std::string::npos) << m;
}

TEST(Polygon, RejectsZeroLengthEdge) {
  const std::string m = validation_message({{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}});
  EXPECT_NE(m.find("edge 1"), std::string::npos) << m;
  EXPECT_NE(m.find("zero length"), std::string::npos) << m;
}

TEST(Polygon, RejectsAnEdgeTooShortToResolveBesideTheOthers) {
  // Found by fuzz_make_map: a unit triangle whose third edge is 1e-309 long
  // passed the exact zero-length test, and its Wachspress map evaluated to NaN.
  const std::string m = validation_message({{0, 0}, {0, -0.00177}, {1, 0}, {1e-309, 1e-309}});
  EXPECT_NE(m.find("edge 3"), std::string::npos) << m;
  EXPECT_NE(m.find("merge the two nearly coincident vertices"), std::string::npos) << m;
  // At the floor's scale, a short edge is still a valid polygon.
  EXPECT_NO_THROW(Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {1e-8, 1}, {0, 1}}));
  EXPECT_NE(validation_message({{0, 0}, {1, 0}, {1, 1}, {1e-10, 1}, {0, 1}}).find("edge 3"),
            std::string::npos);
}

TEST(Polygon, RejectsFoldBackAlongALine) {
  // Vertex 2 goes back along edge 1's line: adjacent edges overlap.
  const std::string m = validation_message({{0, 0}, {2, 0}, {1, 0}, {1, 1}});
  EXPECT_NE(m.find("not simple"), std::string::npos) << m;
}

TEST(Polygon, RejectsTooFewVertices) {
  EXPECT_NE(validation_message({{0, 0}, {1, 0}}).find("2 vertices"), std::string::npos);
}

TEST(Polygon, VertexCountMismatchIsAnError) {
  const Polygon a(square(), "source");
  const Polygon b({{0, 0}, {1, 0}, {0, 1}}, "target");
  try {
    require_same_vertex_count(a, b);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("source has 4 vertices but target has 3"), std::string::npos)
        << e.what();
  }
}

TEST(Polygon, AreaSideAndConvexity) {
  const Polygon sq(square());
  EXPECT_DOUBLE_EQ(sq.signed_area(), 1.0);
  EXPECT_DOUBLE_EQ(sq.perimeter(), 4.0);
  EXPECT_TRUE(sq.is_convex());
  EXPECT_EQ(sq.side_of({0.5, 0.5}), 1);
  EXPECT_EQ(sq.side_of({1.0, 0.5}), 0);
  EXPECT_EQ(sq.side_of({1.5, 0.5}), -1);
  const Polygon l({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
  EXPECT_FALSE(l.is_convex());
  EXPECT_DOUBLE_EQ(l.signed_area(), 3.0);
}
