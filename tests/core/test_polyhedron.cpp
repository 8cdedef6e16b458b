#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "core/polyhedron.hpp"

using namespace warpfem;

namespace {
using Triangles = std::vector<Polyhedron::Triangle>;

std::vector<Point<3>> cube_vertices() {
  std::vector<Point<3>> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  return v;
}

/// The unit cube, two outward triangles per side.
Triangles cube_triangles() {
  return {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
}

std::string validation_message(std::vector<Point<3>> v, Triangles t) {
  try {
    Polyhedron::checked(std::move(v), std::move(t), "test cage");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}
}  // namespace

TEST(Polyhedron, AcceptsOutwardCubeAndMeasuresIt) {
  const Polyhedron p = Polyhedron::checked(cube_vertices(), cube_triangles());
  EXPECT_NEAR(p.signed_volume(), 1.0, 1e-15);
  EXPECT_NEAR(p.surface_area(), 6.0, 1e-14);
  EXPECT_EQ(p.bbox_max(), Point<3>(1, 1, 1));
}

TEST(Polyhedron, RejectsInwardOrientationWithHint) {
  const std::string m = validation_message(
      cube_vertices(), Polyhedron(cube_vertices(), cube_triangles()).reversed().triangles());
  EXPECT_TRUE(contains(m, "oriented inward")) << m;
  EXPECT_TRUE(contains(m, "reverse the orientation")) << m;
}

TEST(Polyhedron, RejectsOneFlippedTriangleNamingIt) {
  Triangles t = cube_triangles();
  std::swap(t[5][1], t[5][2]);
  const std::string m = validation_message(cube_vertices(), t);
  EXPECT_TRUE(contains(m, "same direction")) << m;
  EXPECT_TRUE(contains(m, " 5 ")) << m;
  EXPECT_TRUE(contains(m, "reverse the orientation of one of them")) << m;
}

TEST(Polyhedron, RejectsHoleNamingEdge) {
  Triangles t = cube_triangles();
  t.pop_back();
  const std::string m = validation_message(cube_vertices(), t);
  EXPECT_TRUE(contains(m, "not closed")) << m;
  EXPECT_TRUE(contains(m, "edge")) << m;
}

TEST(Polyhedron, RejectsIndexOutOfRangeAndRepeatedVertex) {
  Triangles t = cube_triangles();
  t[3][0] = 8;
  EXPECT_TRUE(contains(validation_message(cube_vertices(), t), "triangle 3"))
      << validation_message(cube_vertices(), t);
  t = cube_triangles();
  t[4] = {0, 0, 4};
  EXPECT_TRUE(contains(validation_message(cube_vertices(), t), "repeats a vertex"));
}

TEST(Polyhedron, RejectsDegenerateTriangle) {
  // Move vertex 5 onto the line through 1 and 4? Simpler: flatten triangle (0, 2, 1) by putting 2 on the line
  // 0-1.
  auto v = cube_vertices();
  v[2] = Point<3>(0.5, 0, 0);
  const std::string m = validation_message(v, cube_triangles());
  EXPECT_TRUE(contains(m, "degenerate") || contains(m, "intersects itself")) << m;
}

TEST(Polyhedron, RejectsAnEdgeTooShortToResolveBesideTheOthers) {
  // Vertex 7 of the cube pulled to 1e-11 above vertex 3: edge 3-7 is below
  // 1e-9 of the cage's size (the same floor as for polygons).
  auto v = cube_vertices();
  v[7] = Point<3>(1, 1, 1e-11);
  const std::string m = validation_message(v, cube_triangles());
  EXPECT_TRUE(contains(m, "edge 3-7")) << m;
  EXPECT_TRUE(contains(m, "merge the two nearly coincident vertices")) << m;
  v[7] = Point<3>(1, 1, 1e-8);  // short, but resolvable: not refused by this rule
  EXPECT_FALSE(contains(validation_message(v, cube_triangles()), "nearly coincident"));
}

TEST(Polyhedron, RejectsSelfIntersectionNamingTriangles) {
  // Push vertex 7 through the opposite corner: the top and side triangles cross.
  auto v = cube_vertices();
  v[7] = Point<3>(-0.5, -0.5, -0.5);
  const std::string m = validation_message(v, cube_triangles());
  EXPECT_TRUE(contains(m, "intersects itself")) << m;
  EXPECT_TRUE(contains(m, "triangle")) << m;
}

TEST(Polyhedron, RejectsNonManifoldVertex) {
  // Two tetrahedra sharing only vertex 0.
  std::vector<Point<3>> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  Triangles t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}};
  const std::string m = validation_message(v, t);
  EXPECT_TRUE(contains(m, "vertex 0")) << m;
}

TEST(Polyhedron, RejectsNonFiniteAndUnusedVertices) {
  auto v = cube_vertices();
  v[3].x() = std::nan("");
  EXPECT_TRUE(contains(validation_message(v, cube_triangles()), "vertex 3"));
  v = cube_vertices();
  v.emplace_back(2, 2, 2);
  EXPECT_TRUE(contains(validation_message(v, cube_triangles()), "belongs to no triangle"));
}

TEST(Polyhedron, ReadsOffFileAndNamesFileOnError) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string good = (dir / "warpfem_test_cube.off").string();
  {
    std::ofstream f(good);
    f << "OFF\n8 12 0\n";
    for (const auto& p : cube_vertices()) f << p.x() << " " << p.y() << " " << p.z() << "\n";
    for (const auto& t : cube_triangles()) f << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  }
  const Polyhedron p = Polyhedron::read(good);
  EXPECT_EQ(p.triangle_count(), 12);
  EXPECT_NEAR(p.signed_volume(), 1.0, 1e-15);
  const std::string bad = (dir / "warpfem_test_cube_open.off").string();
  {
    std::ofstream f(bad);
    f << "OFF\n8 11 0\n";
    for (const auto& q : cube_vertices()) f << q.x() << " " << q.y() << " " << q.z() << "\n";
    const auto t = cube_triangles();
    for (std::size_t i = 0; i + 1 < t.size(); ++i)
      f << "3 " << t[i][0] << " " << t[i][1] << " " << t[i][2] << "\n";
  }
  try {
    Polyhedron::read(bad);
    ADD_FAILURE() << "an open surface was accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), bad)) << e.what();
    EXPECT_TRUE(contains(e.what(), "not closed")) << e.what();
  }
  EXPECT_THROW(Polyhedron::read((dir / "warpfem_no_such_file.off").string()), Error);
  std::filesystem::remove(good);
  std::filesystem::remove(bad);
}

// The other formats CGAL reads: ASCII STL (every facet with its own copies of
// its vertices, which the reader merges), OBJ and PLY; each gives the same
// closed cube.
TEST(Polyhedron, ReadsStlObjAndPlyFiles) {
  const auto dir = std::filesystem::temp_directory_path();
  const auto vertices = cube_vertices();
  const auto triangles = cube_triangles();
  const auto at = [&](Index i) { return vertices[static_cast<std::size_t>(i)]; };
  // Named by the process, so that two test runs on one host do not collide.
  const std::string tag = std::to_string(::getpid());
  const std::string stl = (dir / ("warpfem_test_cube_" + tag + ".stl")).string(),
                    obj = (dir / ("warpfem_test_cube_" + tag + ".obj")).string(),
                    ply = (dir / ("warpfem_test_cube_" + tag + ".ply")).string();
  {
    std::ofstream f(stl);
    f << "solid cube\n";
    for (const auto& t : triangles) {
      const Point<3> n = (at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0])).normalized();
      f << "facet normal " << n.x() << " " << n.y() << " " << n.z() << "\nouter loop\n";
      for (int k = 0; k < 3; ++k)
        f << "vertex " << at(t[k]).x() << " " << at(t[k]).y() << " " << at(t[k]).z() << "\n";
      f << "endloop\nendfacet\n";
    }
    f << "endsolid cube\n";
  }
  {
    std::ofstream f(obj);
    for (const auto& p : vertices) f << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
    for (const auto& t : triangles) f << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  }
  {
    std::ofstream f(ply);
    f << "ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
         "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& p : vertices) f << p.x() << " " << p.y() << " " << p.z() << "\n";
    for (const auto& t : triangles) f << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  }
  for (const std::string& file : {stl, obj, ply}) {
    const Polyhedron p = Polyhedron::read(file);
    EXPECT_EQ(p.vertex_count(), 8) << file;
    EXPECT_EQ(p.triangle_count(), 12) << file;
    EXPECT_NEAR(p.signed_volume(), 1.0, 1e-15) << file;
    std::filesystem::remove(file);
  }
}

TEST(Polyhedron, SameTriangulationCheck) {
  const Polyhedron a(cube_vertices(), cube_triangles(), "source");
  Triangles t = cube_triangles();
  std::swap(t[0], t[1]);
  const Polyhedron b(cube_vertices(), t, "target");
  EXPECT_NO_THROW(require_same_triangulation(a, a));
  try {
    require_same_triangulation(a, b);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "triangle 0")) << e.what();
  }
}
