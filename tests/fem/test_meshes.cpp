#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/boundary_locator.hpp"
#include "core/mesh/cell_locator.hpp"
#include "core/mesh/gmsh_reader.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/simplex_neighbours.hpp"
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

// A polygon of many edges is searched in CGAL's AABB tree: the same edges, in
// the same order, as a scan over all of them, on and off the boundary.
TEST(BoundaryLocator, ManyEdgesFindTheSameEdgesAsAScan) {
  const Index n = 480;
  std::vector<Point<2>> v;
  for (Index i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    const double r = 1 + 0.1 * std::sin(12 * t);
    v.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  const Polygon wavy = Polygon::checked(v);
  const double tol = 1e-9 * (wavy.bbox_max() - wavy.bbox_min()).norm();
  const BoundaryLocator loc(wavy);
  const auto scan = [&](const Point<2>& x) {
    std::vector<int> found;
    for (Index e = 0; e < n; ++e) {
      const Point<2> a = wavy.vertex(e), d = wavy.vertex(e + 1) - a;
      const double s = std::clamp((x - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      if ((x - (a + s * d)).norm() <= tol) found.push_back(static_cast<int>(e));
    }
    return found;
  };
  std::vector<Point<2>> probes;
  for (Index i = 0; i < n; ++i) {
    const Point<2> a = wavy.vertex(i), b = wavy.vertex(i + 1);
    const Point<2> normal = Point<2>(b.y() - a.y(), a.x() - b.x()).normalized();
    probes.push_back(a);                                 // two edges
    probes.push_back(0.3 * a + 0.7 * b);                 // one edge
    probes.push_back((a + b) / 2 + 0.5 * tol * normal);  // within the tolerance
    probes.push_back((a + b) / 2 + 3 * tol * normal);    // beyond it
    probes.push_back(0.9 * ((a + b) / 2));               // inside, off the boundary
  }
  std::vector<int> found;
  int on_two = 0;
  for (const Point<2>& x : probes) {
    loc.edges_at(x, found);
    const std::vector<int> expected = scan(x);
    ASSERT_EQ(found, expected) << "at (" << x.x() << ", " << x.y() << ")";
    on_two += expected.size() == 2 ? 1 : 0;
    const int nearest = loc.edge_at(x);
    if (expected.empty())
      EXPECT_EQ(nearest, -1);
    else
      EXPECT_NE(std::find(expected.begin(), expected.end(), nearest), expected.end());
  }
  EXPECT_EQ(on_two, n);  // every vertex, and nothing else, lies on two edges
  loc.edges_at(wavy.vertex(0), found);
  EXPECT_EQ(found, std::vector<int>({0, static_cast<int>(n - 1)}));
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

TEST(CellLocator, NearestTriangleInAMeshWithMovedVertices) {
  const Polygon l = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L");
  const Mesh<2> m = mesh_polygon(l, {.max_edge_length = 0.2});
  // The image of the mesh under a smooth bijection: the triangles keep no bounding-box grid structure.
  Points<2> moved(m.num_vertices(), 2);
  for (Index v = 0; v < m.num_vertices(); ++v) {
    const Point<2> x = m.vertex(v);
    moved.row(v) << x.x() + 0.2 * std::sin(x.y()), x.y() + 0.1 * x.x() * x.x();
  }
  const CellLocator loc(moved, m.cells, CellType::triangle);
  auto corner = [&](Index c, int k) -> Point<2> { return moved.row(m.cells(c, k)).transpose(); };
  auto least = [&](Index c, const Point<2>& x) {
    const auto l = barycentric_coordinates(corner(c, 0), corner(c, 1), corner(c, 2), x);
    return std::min({l[0], l[1], l[2]});
  };
  for (Index c = 0; c < m.num_cells(); c += 7) {
    // Interior points, an edge midpoint and a corner of the cell.
    for (const auto& w :
         {std::array<double, 3>{0.2, 0.3, 0.5}, {0.6, 0.3, 0.1}, {0.5, 0.5, 0.0}, {1, 0, 0}}) {
      const Point<2> x = w[0] * corner(c, 0) + w[1] * corner(c, 1) + w[2] * corner(c, 2);
      const CellLocator::Nearest hit = loc.nearest(x);
      ASSERT_GE(hit.cell, 0);
      EXPECT_TRUE(hit.inside);
      const Point<2> back = hit.barycentric[0] * corner(hit.cell, 0) +
                            hit.barycentric[1] * corner(hit.cell, 1) +
                            hit.barycentric[2] * corner(hit.cell, 2);
      EXPECT_LT((back - x).norm(), 1e-13);
      // No triangle holds x more deeply than the one returned (brute force over all of them).
      double deepest = -1e300;
      for (Index d = 0; d < m.num_cells(); ++d) deepest = std::max(deepest, least(d, x));
      EXPECT_EQ(least(hit.cell, x), deepest);
    }
  }
  // Outside the moved mesh: the nearby triangle, with clamped coordinates summing to 1.
  const CellLocator::Nearest out = loc.nearest({-0.3, -0.2});
  ASSERT_GE(out.cell, 0);
  EXPECT_FALSE(out.inside);
  EXPECT_GE(std::min({out.barycentric[0], out.barycentric[1], out.barycentric[2]}), 0.0);
  EXPECT_NEAR(out.barycentric[0] + out.barycentric[1] + out.barycentric[2], 1.0, 1e-15);
  EXPECT_LT(loc.locate({-0.3, -0.2}).cell, 0);
  // locate() agrees with nearest() inside the moved mesh.
  const Point<2> x = (corner(5, 0) + corner(5, 1) + corner(5, 2)) / 3;
  EXPECT_EQ(loc.locate(x).cell, 5);
  EXPECT_EQ(loc.nearest(x).cell, 5);
}

TEST(PolygonMesher, SplitsTheBoundaryIntoPiecesNoLongerThanAsked) {
  const Polygon l = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L");
  for (double h : {0.3, 0.45}) {
    const Mesh<2> m = mesh_polygon(l, {.max_edge_length = 1.0, .max_boundary_edge_length = h});
    double perimeter = 0;
    for (Index f = 0; f < m.num_boundary_facets(); ++f) {
      const double len = (m.vertex(m.boundary_facets(f, 1)) - m.vertex(m.boundary_facets(f, 0))).norm();
      EXPECT_LE(len, h * (1 + 1e-12));
      perimeter += len;
    }
    EXPECT_NEAR(perimeter, 8.0, 1e-12);
    // Every edge split into ceil(length / h) equal pieces, so every split point is a mesh vertex.
    for (Index e = 0; e < l.size(); ++e) {
      const Point<2> a = l.vertex(e), b = l.vertex(e + 1);
      const int pieces = static_cast<int>(std::ceil((b - a).norm() / h));
      for (int j = 0; j < pieces; ++j) {
        const Point<2> p = a + (b - a) * (static_cast<double>(j) / pieces);
        double closest = 1e300;
        for (Index v = 0; v < m.num_vertices(); ++v) closest = std::min(closest, (m.vertex(v) - p).norm());
        EXPECT_LT(closest, 1e-14) << "edge " << e << " piece " << j;
      }
    }
  }
}

template <int dim>
void expect_consistent_neighbours(const Mesh<dim>& m) {
  const IndexTable nb = simplex_neighbours(m);
  ASSERT_EQ(nb.rows(), m.num_cells());
  ASSERT_EQ(nb.cols(), dim + 1);
  Index boundary = 0;
  for (Index c = 0; c < m.num_cells(); ++c)
    for (int i = 0; i <= dim; ++i) {
      const Index d = nb(c, i);
      if (d < 0) {
        ++boundary;
        continue;
      }
      // d shares the facet of c opposite vertex i, and its own opposite vertex is not a vertex of c.
      int shared = 0, back = 0;
      for (int k = 0; k <= dim; ++k) {
        const Index v = m.cells(d, k);
        bool in_c = false;
        for (int j = 0; j <= dim; ++j) in_c = in_c || (j != i && m.cells(c, j) == v);
        shared += in_c;
        if (!in_c) {
          EXPECT_EQ(nb(d, k), c);
        }
        back += nb(d, k) == c;
      }
      EXPECT_EQ(shared, dim);
      EXPECT_EQ(back, 1);
    }
  EXPECT_EQ(boundary, m.num_boundary_facets());
}

TEST(SimplexNeighbours, SymmetricAndBoundaryFacetsHaveNone) {
  const Polygon l = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L");
  expect_consistent_neighbours(mesh_polygon(l, {.max_edge_length = 0.3}));
  expect_consistent_neighbours(
      structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 2, 1), {2, 3, 2}, CellType::tetrahedron));
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
    EXPECT_NE(std::string(e.what()).find("test_square_v2.msh: mesh.file: the mesh covers area 1"),
              std::string::npos)
        << e.what();
  }
}
