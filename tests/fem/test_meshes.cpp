#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/mesh/boundary_locator.hpp"
#include "core/mesh/cell_locator.hpp"
#include "core/mesh/gmsh_reader.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"

using namespace warpfem;

namespace {
Polygon square16() {
  std::vector<Point<2>> v;
  for (int k = 0; k < 4; ++k) v.emplace_back(k / 4.0, 0);
  for (int k = 0; k < 4; ++k) v.emplace_back(1, k / 4.0);
  for (int k = 0; k < 4; ++k) v.emplace_back(1 - k / 4.0, 1);
  for (int k = 0; k < 4; ++k) v.emplace_back(0, 1 - k / 4.0);
  return Polygon::checked(v, "square16");
}
}  // namespace

TEST(StructuredMesh, QuadsAndTrianglesOnARectangleCarryingExtraVertices) {
  const Polygon sq = square16();
  EXPECT_TRUE(is_axis_aligned_rectangle(sq));
  const Mesh<2> q = structured_mesh(sq, 3, 2, CellType::quadrilateral);
  EXPECT_EQ(q.num_cells(), 6);
  EXPECT_EQ(q.num_boundary_facets(), 10);
  const Mesh<2> t = structured_mesh(sq, 3, 2, CellType::triangle);
  EXPECT_EQ(t.num_cells(), 12);
  EXPECT_THROW(structured_mesh(Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}), 2, 2,
                               CellType::triangle),
               Error);
}

TEST(BoundaryLocator, PointsOnEdgesAndVertices) {
  const BoundaryLocator loc(square16());
  std::vector<int> e;
  loc.edges_at({0.1, 0.0}, e);
  EXPECT_EQ(e, std::vector<int>({0}));
  loc.edges_at({0.25, 0.0}, e);  // a polygon vertex: both adjacent edges
  EXPECT_EQ(e, std::vector<int>({0, 1}));
  loc.edges_at({0.5, 0.5}, e);
  EXPECT_TRUE(e.empty());
}

TEST(QuadSplit, CoversThePolygonWithCounterClockwiseQuads) {
  const Polygon l = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
  const Mesh<2> q = split_into_quadrilaterals(mesh_polygon(l, {.max_edge_length = 0.5}));
  double area = 0;
  for (Index c = 0; c < q.num_cells(); ++c) {
    double a = 0;
    for (int k = 0; k < 4; ++k) {
      const Point<2> p = q.vertex(q.cells(c, k)), r = q.vertex(q.cells(c, (k + 1) % 4));
      a += 0.5 * (p.x() * r.y() - r.x() * p.y());
    }
    EXPECT_GT(a, 0);
    area += a;
  }
  EXPECT_NEAR(area, 3.0, 1e-12);
}

TEST(CellLocator, FindsCellsAndReferenceCoordinates) {
  for (CellType type : {CellType::triangle, CellType::quadrilateral}) {
    const Mesh<2> m = structured_mesh(square16(), 5, 4, type);
    const CellLocator loc(m);
    for (double x : {0.0, 0.13, 0.5, 0.999, 1.0})
      for (double y : {0.0, 0.31, 0.77, 1.0}) {
        const auto found = loc.locate({x, y});
        ASSERT_GE(found.cell, 0) << x << "," << y;
      }
    EXPECT_LT(loc.locate({1.5, 0.5}).cell, 0);
  }
}

TEST(GmshReader, ReadsFormat22AndFormat41) {
  std::filesystem::create_directories("output");
  {
    std::ofstream v2("output/test_square_v2.msh");
    v2 << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0.5 "
          "0\n$EndNodes\n"
       << "$Elements\n5\n1 1 2 0 1 1 2\n2 2 2 0 1 1 2 5\n3 2 2 0 1 2 3 5\n4 2 2 0 1 3 4 5\n5 2 2 0 1 4 1 "
          "5\n$EndElements\n";
  }
  const Polygon sq = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  const Mesh<2> m2 = read_gmsh("output/test_square_v2.msh", sq);
  EXPECT_EQ(m2.num_cells(), 4);
  EXPECT_EQ(m2.num_vertices(), 5);
  EXPECT_EQ(m2.num_boundary_facets(), 4);
  {
    std::ofstream v4("output/test_square_v4.msh");
    v4 << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 "
          "0\n0 1 0\n$EndNodes\n"
       << "$Elements\n1 1 1 1\n2 1 3 1\n1 4 3 2 1\n$EndElements\n";  // clockwise on purpose
  }
  const Mesh<2> m4 = read_gmsh("output/test_square_v4.msh", sq);
  EXPECT_EQ(m4.cell_type, CellType::quadrilateral);
  EXPECT_EQ(m4.num_cells(), 1);
  // Reoriented counter-clockwise.
  const Point<2> a = m4.vertex(m4.cells(0, 0)), b = m4.vertex(m4.cells(0, 1)), c = m4.vertex(m4.cells(0, 2));
  EXPECT_GT((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x(), 0);
  // A mesh of the wrong domain is rejected with the file name.
  const Polygon big = Polygon::checked({{0, 0}, {2, 0}, {2, 2}, {0, 2}});
  try {
    read_gmsh("output/test_square_v2.msh", big);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("test_square_v2.msh: /mesh/file: the mesh covers area 1"),
              std::string::npos)
        << e.what();
  }
}
