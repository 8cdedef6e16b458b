// Structured meshes of an axis-aligned box (hexahedra and Kuhn tetrahedra):
// volume, orientation, boundary facets on their tagged box faces and outward,
// conformity (every interior facet shared by exactly two cells) and Euler's formula.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>
#include <set>

#include "core/error.hpp"
#include "core/mesh/quadrature.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "fem/reference/lagrange_element.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {

struct BoxCase {
  CellType type;
  std::array<int, 3> n;
};
std::string box_name(const ::testing::TestParamInfo<BoxCase>& info) {
  return to_string(info.param.type) + "_" + std::to_string(info.param.n[0]) + "x" +
         std::to_string(info.param.n[1]) + "x" + std::to_string(info.param.n[2]);
}

const Point<3> lo(-1.0, 0.5, 2.0), hi(2.0, 1.25, 3.5);

Mesh<3> box_mesh(const BoxCase& c) {
  return structured_box_mesh(lo, hi, c.n, c.type);
}

// Outward normal of a facet: cross product of its diagonals (quadrilateral) or edges (triangle).
Point<3> facet_normal(const Mesh<3>& m, const std::vector<TableIndex>& f) {
  const auto x = [&](int k) { return m.vertex(f[k]); };
  if (f.size() == 3) return (x(1) - x(0)).cross(x(2) - x(0));
  return (x(2) - x(0)).cross(x(3) - x(1));
}

class StructuredBox : public ::testing::TestWithParam<BoxCase> {};

}  // namespace

TEST_P(StructuredBox, CellsArePositiveAndFillTheBox) {
  const Mesh<3> m = box_mesh(GetParam());
  const auto [nx, ny, nz] = GetParam().n;
  EXPECT_EQ(m.num_vertices(), static_cast<Index>(nx + 1) * (ny + 1) * (nz + 1));
  EXPECT_EQ(m.num_cells(), static_cast<Index>(nx) * ny * nz * (m.cell_type == CellType::tetrahedron ? 6 : 1));
  // Volume = sum over cells of the integral of det J (Q1/P1 geometry), which is
  // positive at every quadrature point.
  const LagrangeElement<3> geo(m.cell_type, 1);
  const auto rule = cell_quadrature<3>(m.cell_type, 3);
  const auto grad = geo.gradients(rule.points);
  double volume = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    Points<3> x(geo.num_dofs(), 3);
    for (int v = 0; v < geo.num_dofs(); ++v) x.row(v) = m.vertices.row(m.cells(c, v));
    for (Index q = 0; q < rule.size(); ++q) {
      Matrix<3> J;
      for (int d = 0; d < 3; ++d) J.col(d) = (grad[d].row(q) * x).transpose();
      ASSERT_GT(J.determinant(), 0.0) << "cell " << c;
      volume += rule.weights(q) * J.determinant();
    }
  }
  EXPECT_NEAR(volume, (hi - lo).prod(), 1e-12);
  // Every vertex inside the box.
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(m.vertices.col(d).minCoeff(), lo(d));
    EXPECT_EQ(m.vertices.col(d).maxCoeff(), hi(d));
  }
}

TEST_P(StructuredBox, BoundaryFacetsAreOutwardOnTheirTaggedFace) {
  const Mesh<3> m = box_mesh(GetParam());
  const auto [nx, ny, nz] = GetParam().n;
  const Index per_hex = m.cell_type == CellType::tetrahedron ? 2 : 1;
  EXPECT_EQ(m.num_boundary_facets(), 2 * per_hex * (static_cast<Index>(nx) * ny + ny * nz + nz * nx));
  EXPECT_EQ(m.boundary_facets.cols(), m.cell_type == CellType::tetrahedron ? 3 : 4);
  ASSERT_EQ(m.facet_tags.size(), static_cast<std::size_t>(m.num_boundary_facets()));
  std::array<Index, 6> per_face{};
  std::array<double, 6> area{};
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    const int tag = m.facet_tags[f];
    ASSERT_GE(tag, 0);
    ASSERT_LT(tag, 6);
    const int axis = tag / 2;
    const double plane = tag % 2 == 0 ? lo(axis) : hi(axis);
    std::vector<TableIndex> fv(m.boundary_facets.row(f).data(),
                               m.boundary_facets.row(f).data() + m.boundary_facets.cols());
    for (TableIndex v : fv) EXPECT_EQ(m.vertices(v, axis), plane) << "facet " << f << " tag " << tag;
    const Point<3> normal = facet_normal(m, fv);
    Point<3> outward = Point<3>::Zero();
    outward(axis) = tag % 2 == 0 ? -1 : 1;
    EXPECT_GT(normal.dot(outward), 0.0) << "facet " << f << " not outward";
    EXPECT_NEAR(normal.cross(outward).norm(), 0.0, 1e-12) << "facet " << f << " not planar on its face";
    ++per_face[tag];
    area[tag] += 0.5 * normal.norm();  // half the diagonal (edge) cross product: quad (triangle) area
  }
  const Index faces[3] = {static_cast<Index>(ny) * nz, static_cast<Index>(nz) * nx,
                          static_cast<Index>(nx) * ny};
  for (int t = 0; t < 6; ++t) {
    EXPECT_EQ(per_face[t], per_hex * faces[t / 2]) << "face " << t;
    const int a = (t / 2 + 1) % 3, b = (t / 2 + 2) % 3;
    EXPECT_NEAR(area[t], (hi(a) - lo(a)) * (hi(b) - lo(b)), 1e-12) << "face " << t;
  }
}

TEST_P(StructuredBox, ConformingWithEulerCharacteristicOne) {
  const Mesh<3> m = box_mesh(GetParam());
  const auto& faces = cell_faces(m.cell_type);
  // Facet -> outward normals of the cells using it.
  std::map<std::vector<TableIndex>, std::vector<Point<3>>> facets;
  std::set<std::pair<TableIndex, TableIndex>> edges;
  for (Index c = 0; c < m.num_cells(); ++c) {
    for (const auto& f : faces) {
      std::vector<TableIndex> fv;
      for (int v : f) fv.push_back(m.cells(c, v));
      const Point<3> normal = facet_normal(m, fv);
      std::sort(fv.begin(), fv.end());
      facets[fv].push_back(normal);
    }
    for (const auto& e : cell_edges(m.cell_type))
      edges.insert(std::minmax(m.cells(c, e[0]), m.cells(c, e[1])));
  }
  Index boundary = 0;
  for (const auto& [key, normals] : facets) {
    ASSERT_LE(normals.size(), 2u) << "facet shared by more than two cells";
    if (normals.size() == 1)
      ++boundary;
    else  // the two cells lie on opposite sides
      EXPECT_LT(normals[0].dot(normals[1]), 0.0);
  }
  EXPECT_EQ(boundary, m.num_boundary_facets());
  // V - E + F - C = 1 for a mesh of a ball.
  EXPECT_EQ(
      m.num_vertices() - static_cast<Index>(edges.size()) + static_cast<Index>(facets.size()) - m.num_cells(),
      1);
}

TEST_P(StructuredBox, MaxEdgeLength) {
  const auto c = GetParam();
  const Mesh<3> m = box_mesh(c);
  Point<3> h;
  for (int d = 0; d < 3; ++d) h(d) = (hi(d) - lo(d)) / c.n[d];
  // Hexahedron edges run along the axes; every Kuhn tetrahedron has the box diagonal as an edge.
  const double expected = c.type == CellType::hexahedron ? h.maxCoeff() : h.norm();
  EXPECT_NEAR(m.max_edge_length(), expected, 1e-14);
}

INSTANTIATE_TEST_SUITE_P(Boxes, StructuredBox,
                         ::testing::Values(BoxCase{CellType::hexahedron, {1, 1, 1}},
                                           BoxCase{CellType::hexahedron, {2, 3, 4}},
                                           BoxCase{CellType::tetrahedron, {1, 1, 1}},
                                           BoxCase{CellType::tetrahedron, {3, 2, 2}}),
                         box_name);

TEST(StructuredBoxMesh, BadInputIsAClearError) {
  EXPECT_THROW(structured_box_mesh(lo, hi, {0, 1, 1}, CellType::hexahedron), Error);
  EXPECT_THROW(structured_box_mesh(hi, lo, {1, 1, 1}, CellType::hexahedron), Error);
  EXPECT_THROW(structured_box_mesh(lo, hi, {1, 1, 1}, CellType::triangle), Error);
}
