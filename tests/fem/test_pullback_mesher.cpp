// Coarse meshes of Ω0 pulled back from a Delaunay mesh of the target Ω1.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/pullback_mesher.hpp"
#include "io/run_config.hpp"
#include "mapping/make_map.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {
Polygon l_shape() {
  return Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L-shape");
}

/// The L-shape with its re-entrant corner pulled (the bench's "bent L"): every angle changes.
mapping::MapSpec bent_l_map() {
  mapping::MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = l_shape();
  spec.target = Polygon::checked({{0, 0}, {2, 0}, {2.2, 1.4}, {1.3, 0.8}, {1.1, 2}, {-0.2, 1.8}}, "bent L");
  return spec;
}

double signed_area(const Point<2>& a, const Point<2>& b, const Point<2>& c) {
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

double distance_to_segment(const Point<2>& p, const Point<2>& a, const Point<2>& b) {
  const Point<2> d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}

/// Checks what every pulled-back mesh must satisfy: cells counter-clockwise in Ω0 and covering
/// it, boundary facets on the source edge they are tagged with, and the warped vertices
/// forming a shape-regular mesh of the target (the Delaunay mesh that was pulled back).
void expect_valid_pullback(const Mesh<2>& mesh, const Polygon& source, const Polygon& target,
                           const mapping::Map<2>& map, double min_target_angle_degrees) {
  Points<2> y;
  map.eval(mesh.vertices, y);
  double area = 0;
  double min_angle = 180;
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    double cell_min = 180;
    const Point<2> a = mesh.vertex(mesh.cells(c, 0)), b = mesh.vertex(mesh.cells(c, 1)),
                   d = mesh.vertex(mesh.cells(c, 2));
    EXPECT_GT(signed_area(a, b, d), 0) << "cell " << c << " folds in Ω0";
    area += signed_area(a, b, d);
    for (int k = 0; k < 3; ++k) {
      const Point<2> p = y.row(mesh.cells(c, k)).transpose(),
                     q = y.row(mesh.cells(c, (k + 1) % 3)).transpose(),
                     r = y.row(mesh.cells(c, (k + 2) % 3)).transpose();
      cell_min = std::min(cell_min, std::acos((q - p).normalized().dot((r - p).normalized())) * 180 / M_PI);
    }
    min_angle = std::min(min_angle, cell_min);
  }
  std::printf("%ld cells, smallest warped angle %.1f°\n", static_cast<long>(mesh.num_cells()), min_angle);
  EXPECT_NEAR(area, source.signed_area(), 1e-10);
  EXPECT_GE(min_angle, min_target_angle_degrees) << "the warped vertices are not the target's Delaunay mesh";
  ASSERT_EQ(mesh.facet_tags.size(), static_cast<std::size_t>(mesh.num_boundary_facets()));
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f) {
    const int e = mesh.facet_tags[f];
    for (int k = 0; k < 2; ++k) {
      const Index v = mesh.boundary_facets(f, k);
      EXPECT_LE(distance_to_segment(mesh.vertex(v), source.vertex(e), source.vertex(e + 1)), 1e-14);
      EXPECT_LE(distance_to_segment(y.row(v).transpose(), target.vertex(e), target.vertex(e + 1)), 1e-10);
    }
  }
}
}  // namespace

TEST(PullbackMesher, IdentityMapGivesTheSourceMesh) {
  const Polygon l = l_shape();
  const mapping::IdentityMap<2> identity;
  PullbackReport report;
  const Mesh<2> pulled = pull_back_target_mesh(l, l, identity, {.max_edge_length = 0.3}, &report);
  const Mesh<2> direct = mesh_polygon(l, {.max_edge_length = 0.3});
  ASSERT_EQ(pulled.num_vertices(), direct.num_vertices());
  ASSERT_EQ(pulled.num_cells(), direct.num_cells());
  EXPECT_LE((pulled.vertices - direct.vertices).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(report.fold_repairs, 0);
  EXPECT_NEAR(report.max_distortion, 1.0, 1e-9);  // the identity is affine on every cell
  expect_valid_pullback(pulled, l, l, identity, 20.0);
}

TEST(PullbackMesher, WarpedVerticesAreTheTargetMesh) {
  const mapping::MapSpec spec = bent_l_map();
  const mapping::MapPtr<2> f = mapping::make_map(spec);
  PullbackReport report;
  const Mesh<2> mesh =
      pull_back_target_mesh(*spec.source, *spec.target, *f, {.max_edge_length = 0.3}, &report);
  EXPECT_LE(report.max_residual, 1e-10);
  // The same vertices as CGAL's mesh of the target (Newton converged, corners exact).
  const Mesh<2> target_mesh = mesh_polygon(*spec.target, {.max_edge_length = 0.3});
  EXPECT_EQ(mesh.num_vertices(), target_mesh.num_vertices());
  Points<2> y;
  f->eval(mesh.vertices, y);
  EXPECT_LE((y - target_mesh.vertices).cwiseAbs().maxCoeff(), 1e-10);
  for (Index i = 0; i < spec.source->size(); ++i) {
    bool found = false;
    for (Index v = 0; v < mesh.num_vertices(); ++v) found |= mesh.vertex(v) == spec.source->vertex(i);
    EXPECT_TRUE(found) << "source corner " << i << " is not a mesh vertex";
  }
  expect_valid_pullback(mesh, *spec.source, *spec.target, *f, 20.0);
}

// The gear: target triangles with three boundary vertices around convex tooth corners are
// degenerate in Ω0 (the square's side is straight there), and other cells fold; the repairs
// (extra target vertices) must leave a valid mesh of the square whose image is still
// CGAL's shape-bounded Delaunay mesh of the gear.
TEST(PullbackMesher, RepairsEarsAndFoldsOnTheGear) {
  const std::string file = "examples/study_gear64.json";  // tests run in the source directory
  const mapping::MapSpec spec =
      io::parse_required_map(io::ConfigNode(io::ConfigNode::parse_file(file), file));
  const mapping::MapPtr<2> f = mapping::make_map(spec);
  for (const double h : {0.5, 0.3, 0.15}) {
    PullbackReport report;
    const Mesh<2> mesh =
        pull_back_target_mesh(*spec.source, *spec.target, *f, {.max_edge_length = h}, &report);
    SCOPED_TRACE("h = " + std::to_string(h));
    EXPECT_LE(report.max_residual, 1e-10);
    expect_valid_pullback(mesh, *spec.source, *spec.target, *f, 20.0);
  }
}

TEST(PullbackMesher, MeshFactoryBuildsPullbackMeshesAndQuadrilaterals) {
  const mapping::MapSpec spec = bent_l_map();
  const mapping::MapPtr<2> f = mapping::make_map(spec);
  MeshSpec ms;
  ms.type = "pullback";
  ms.max_edge_length = 0.4;
  const Mesh<2> tri = make_coarse_mesh(*spec.source, *spec.target, *f, ms);
  EXPECT_EQ(tri.cell_type, CellType::triangle);
  ms.cell_type = CellType::quadrilateral;
  const Mesh<2> quad = make_coarse_mesh(*spec.source, *spec.target, *f, ms);
  EXPECT_EQ(quad.cell_type, CellType::quadrilateral);
  EXPECT_EQ(quad.num_cells(), 3 * tri.num_cells());
  // Without the map the factory cannot pull back: a clear error naming the field.
  try {
    make_coarse_mesh(*spec.source, ms);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.type"), std::string::npos) << e.what();
  }
}

TEST(PullbackMesher, RejectsPolygonsWithDifferentVertexCounts) {
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "square");
  const mapping::IdentityMap<2> identity;
  try {
    pull_back_target_mesh(l_shape(), square, identity, {.max_edge_length = 0.3});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("map.target"), std::string::npos) << e.what();
  }
}

TEST(PullbackMesher, ConfigAcceptsThePullbackType) {
  const nlohmann::json json = nlohmann::json::parse(R"({"type": "pullback", "max_edge_length": 0.2})");
  const MeshSpec spec = io::parse_mesh_spec(io::ConfigNode(json, "test.json"));
  EXPECT_EQ(spec.type, "pullback");
  EXPECT_EQ(spec.cell_type, CellType::triangle);
  EXPECT_DOUBLE_EQ(spec.max_edge_length, 0.2);
}
