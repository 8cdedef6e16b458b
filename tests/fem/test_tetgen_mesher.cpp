// Tetrahedral meshes of polyhedra by TetGen: the mesh fills exactly the
// polyhedron (volume), its boundary is exactly the input surface with the
// input's orientation and tags, cells are positively oriented and the volume
// bound holds; bad surfaces and options are refused with the polyhedron's name.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <set>

#include "core/error.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/tetgen_mesher.hpp"
#include "tests/mapping/test_polyhedra.hpp"

using namespace warpfem;

namespace {

Real cell_volume(const Mesh<3>& m, Index c) {
  Matrix<3> e;
  for (int k = 0; k < 3; ++k) e.col(k) = m.vertex(m.cells(c, k + 1)) - m.vertex(m.cells(c, 0));
  return e.determinant() / 6;
}

/// Each facet as its vertex triple rotated so the smallest index comes first (keeps orientation).
std::set<std::array<Index, 3>> oriented_faces(const IndexTable& facets) {
  std::set<std::array<Index, 3>> s;
  for (Index f = 0; f < facets.rows(); ++f) {
    std::array<Index, 3> t{facets(f, 0), facets(f, 1), facets(f, 2)};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    s.insert(t);
  }
  return s;
}

void expect_fills(const Polyhedron& P, const Mesh<3>& m) {
  Real volume = 0, smallest = 1;
  for (Index c = 0; c < m.num_cells(); ++c) {
    volume += cell_volume(m, c);
    smallest = std::min(smallest, cell_volume(m, c));
  }
  EXPECT_GT(smallest, 0) << "a cell is not positively oriented";
  EXPECT_NEAR(volume, P.signed_volume(), 1e-12 * std::abs(P.signed_volume()));
  for (Index i = 0; i < P.vertex_count(); ++i) EXPECT_EQ(m.vertex(i), P.vertex(i));
  // The boundary of the cells (outward by cell orientation) is the input surface, as given.
  IndexTable input(P.triangle_count(), 3);
  for (Index t = 0; t < P.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) input(t, k) = static_cast<TableIndex>(P.triangle(t)[k]);
  EXPECT_EQ(oriented_faces(find_boundary_facets(m)), oriented_faces(input));
  EXPECT_EQ(oriented_faces(m.boundary_facets), oriented_faces(input));
  ASSERT_EQ(m.facet_tags.size(), static_cast<std::size_t>(P.triangle_count()));
}

std::string message_of(const Polyhedron& P, const TetrahedralMeshOptions& o) {
  try {
    mesh_polyhedron(P, o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TetgenMesher, FillsNonConvexPolyhedronWithItsSurfaceAsBoundary) {
  const Polyhedron P = mapping::test::bumpy_sphere();
  const Mesh<3> m = mesh_polyhedron(P);
  expect_fills(P, m);
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    // Facet f is input triangle f, tagged with its index by default.
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.boundary_facets(f, k), P.triangle(f)[k]);
    EXPECT_EQ(m.facet_tags[static_cast<std::size_t>(f)], f);
  }
}

TEST(TetgenMesher, VolumeBoundHoldsWhenTheSurfaceMaySplit) {
  const Polyhedron P = mapping::test::subdivided_cube(3);
  TetrahedralMeshOptions o;
  o.max_volume = 1e-3;
  o.quality_ratio = 1.5;
  o.keep_surface = false;
  const Mesh<3> m = mesh_polyhedron(P, o);
  Real volume = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    EXPECT_GT(cell_volume(m, c), 0);
    EXPECT_LE(cell_volume(m, c), 1e-3 * (1 + 1e-9));
    volume += cell_volume(m, c);
  }
  EXPECT_NEAR(volume, 1.0, 1e-12);
  // Outward facets, each inside the input triangle its tag names; together they cover every triangle.
  EXPECT_EQ(oriented_faces(m.boundary_facets), oriented_faces(find_boundary_facets(m)));
  std::vector<Real> covered(static_cast<std::size_t>(P.triangle_count()), 0.0);
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    const auto& tri = P.triangle(m.facet_tags[static_cast<std::size_t>(f)]);
    const Point<3> a = P.vertex(tri[0]), b = P.vertex(tri[1]), c = P.vertex(tri[2]);
    const Point<3> normal = (b - a).cross(c - a);
    const Point<3> p0 = m.vertex(m.boundary_facets(f, 0)), p1 = m.vertex(m.boundary_facets(f, 1)),
                   p2 = m.vertex(m.boundary_facets(f, 2));
    const Point<3> facet_normal = (p1 - p0).cross(p2 - p0);
    for (const Point<3>& q : {p0, p1, p2}) {
      EXPECT_NEAR(normal.dot(q - a), 0, 1e-14);
      // Barycentric coordinates within the triangle.
      EXPECT_GE(normal.dot((b - a).cross(q - a)), -1e-14);
      EXPECT_GE(normal.dot((c - b).cross(q - b)), -1e-14);
      EXPECT_GE(normal.dot((a - c).cross(q - c)), -1e-14);
    }
    EXPECT_GT(facet_normal.dot(normal), 0) << "facet " << f << " is not outward";
    covered[static_cast<std::size_t>(m.facet_tags[static_cast<std::size_t>(f)])] += 0.5 * facet_normal.norm();
  }
  for (Index t = 0; t < P.triangle_count(); ++t) {
    const auto& tri = P.triangle(t);
    const Real area =
        0.5 * (P.vertex(tri[1]) - P.vertex(tri[0])).cross(P.vertex(tri[2]) - P.vertex(tri[0])).norm();
    EXPECT_NEAR(covered[static_cast<std::size_t>(t)], area, 1e-13) << "triangle " << t;
  }
}

TEST(TetgenMesher, CarriesGivenTrianglePartIds) {
  const Polyhedron P = mapping::test::subdivided_cube(2);
  TetrahedralMeshOptions o;
  for (Index t = 0; t < P.triangle_count(); ++t) {
    // Part id = the side of the cube the triangle lies on (its normal's axis and sign).
    const auto& tri = P.triangle(t);
    const Point<3> n = (P.vertex(tri[1]) - P.vertex(tri[0])).cross(P.vertex(tri[2]) - P.vertex(tri[0]));
    Index axis;
    n.cwiseAbs().maxCoeff(&axis);
    o.triangle_tags.push_back(static_cast<int>(2 * axis + (n(axis) > 0)));
  }
  const Mesh<3> m = mesh_polyhedron(P, o);
  expect_fills(P, m);
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    const int tag = m.facet_tags[static_cast<std::size_t>(f)];
    const int axis = tag / 2;
    const Real plane = tag % 2;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.vertex(m.boundary_facets(f, k))(axis), plane);
  }
}

TEST(TetgenMesher, RefusesSelfIntersectingSurfaceAndBadOptions) {
  // Two cubes overlapping in a corner: closed and outward, but self-intersecting.
  const Polyhedron cube = mapping::test::unit_cube();
  std::vector<Point<3>> v = cube.vertices();
  std::vector<Polyhedron::Triangle> t = cube.triangles();
  for (const auto& p : cube.vertices()) v.push_back(p + Point<3>(0.5, 0.5, 0.5));
  for (const auto& tri : cube.triangles()) t.push_back({tri[0] + 8, tri[1] + 8, tri[2] + 8});
  const Polyhedron overlapping(v, t, "overlapping cubes");
  const std::string m = message_of(overlapping, {});
  EXPECT_NE(m.find("overlapping cubes"), std::string::npos) << m;
  EXPECT_NE(m.find("intersect"), std::string::npos) << m;

  TetrahedralMeshOptions o;
  o.quality_ratio = 1.0;
  const std::string q = message_of(cube, o);
  EXPECT_NE(q.find("unit cube: quality ratio 1 cannot be used"), std::string::npos) << q;
  o = {};
  o.triangle_tags = {1, 2, 3};
  const std::string tags = message_of(cube, o);
  EXPECT_NE(tags.find("3 triangle tags for 12 triangles"), std::string::npos) << tags;
}
