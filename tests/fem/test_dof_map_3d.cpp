// DofMap<3> on structured box meshes (hexahedra and Kuhn tetrahedra): entity
// counts against Euler's formula and the facet count of a closed cell
// complex; every DOF of P2/Q2 computed from each cell containing it lands on
// the same physical point, distinct DOFs on distinct points; facet_dofs
// follows the facet element's node order; the 3D output mesh shares exactly
// these nodes.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <tuple>
#include <vector>

#include "core/mesh/face_numbering.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/postprocessing/output_mesh.hpp"
#include "mapping/map.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {

struct BoxCase {
  CellType type;
  std::array<int, 3> n;
};

class DofMap3d : public ::testing::TestWithParam<BoxCase> {};

/// A box mesh with its interior vertices moved randomly (up to a fifth of a
/// cell): hexahedra become non-affine, so a face node is a genuinely bilinear
/// average and misnumbered nodes cannot coincide by symmetry.
Mesh<3> jiggled_box(const BoxCase& c) {
  const Point<3> lo(-1.0, 0.5, 2.0), hi(2.0, 1.25, 3.5);
  Mesh<3> m = structured_box_mesh(lo, hi, c.n, c.type);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (Index v = 0; v < m.num_vertices(); ++v)
    for (int d = 0; d < 3; ++d) {
      const double h = (hi(d) - lo(d)) / c.n[static_cast<std::size_t>(d)];
      const double x = m.vertices(v, d);
      if (x > lo(d) + 1e-9 && x < hi(d) - 1e-9) m.vertices(v, d) = x + u(rng) * h;
    }
  return m;
}

/// Physical position of local node k of cell c (straight P1/Q1 cell geometry).
Point<3> node_position(const Mesh<3>& m, const LagrangeElement<3>& element, Index c, int k) {
  const LagrangeElement<3> geo(m.cell_type, 1);
  const MatrixX N = geo.values(element.nodes());
  Point<3> x = Point<3>::Zero();
  for (int v = 0; v < geo.num_dofs(); ++v) x += N(k, v) * m.vertex(m.cells(c, v));
  return x;
}

}  // namespace

TEST_P(DofMap3d, EntityCountsSatisfyEulersFormula) {
  const auto [nx, ny, nz] = GetParam().n;
  const Mesh<3> m = structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), GetParam().n, GetParam().type);
  const EdgeNumbering edges(m);
  const FaceNumbering faces(m);
  const Index V = m.num_vertices(), E = edges.num_edges(), F = faces.num_faces(), C = m.num_cells();
  // A closed 3-ball: V − E + F − C = 1; every interior face has two cells, a boundary face one.
  EXPECT_EQ(V - E + F - C, 1);
  const Index faces_per_cell = static_cast<Index>(cell_faces(m.cell_type).size());
  EXPECT_EQ(2 * F - m.num_boundary_facets(), faces_per_cell * C);
  if (m.cell_type == CellType::hexahedron) {
    EXPECT_EQ(
        E, Index{nx} * (ny + 1) * (nz + 1) + Index{nx + 1} * ny * (nz + 1) + Index{nx + 1} * (ny + 1) * nz);
    EXPECT_EQ(F, Index{nx + 1} * ny * nz + Index{nx} * (ny + 1) * nz + Index{nx} * ny * (nz + 1));
  }
  // The DOF maps count the same entities: P2 vertices + edges, Q2 + faces + cells.
  const DofMap<3> second(m, LagrangeElement<3>(m.cell_type, 2));
  EXPECT_EQ(second.num_edges(), E);
  if (m.cell_type == CellType::hexahedron) {
    EXPECT_EQ(second.num_faces(), F);
    EXPECT_EQ(second.num_dofs(), V + E + F + C);
    EXPECT_EQ(second.num_dofs(), Index{2 * nx + 1} * (2 * ny + 1) * (2 * nz + 1));
  } else {
    EXPECT_EQ(second.num_faces(), 0);
    EXPECT_EQ(second.num_dofs(), V + E);
  }
  // P1/Q1: the vertices, and the mesh's own tables.
  const DofMap<3> first(m, LagrangeElement<3>(m.cell_type, 1));
  EXPECT_TRUE(first.dofs_are_vertices());
  EXPECT_EQ(first.num_dofs(), V);
  EXPECT_EQ(&first.cell_dofs(), &m.cells);
  EXPECT_EQ(&first.dof_points(), &m.vertices);
}

TEST_P(DofMap3d, SharedDofsHaveOnePhysicalPointAndDistinctDofsDistinctPoints) {
  const Mesh<3> m = jiggled_box(GetParam());
  for (int order : {1, 2}) {
    const LagrangeElement<3> element(m.cell_type, order);
    const DofMap<3> dofs(m, element);
    const IndexTable& cd = dofs.cell_dofs();
    ASSERT_EQ(cd.rows(), m.num_cells());
    ASSERT_EQ(cd.cols(), element.num_dofs());
    std::vector<int> uses(static_cast<std::size_t>(dofs.num_dofs()), 0);
    for (Index c = 0; c < m.num_cells(); ++c)
      for (int k = 0; k < element.num_dofs(); ++k) {
        const Index d = cd(c, k);
        ASSERT_GE(d, 0);
        ASSERT_LT(d, dofs.num_dofs());
        ++uses[static_cast<std::size_t>(d)];
        // Each cell's own element nodes give the DOF's point.
        ASSERT_LT((node_position(m, element, c, k) - dofs.dof_points().row(d).transpose()).norm(), 1e-12)
            << element.name() << " cell " << c << " node " << k;
      }
    EXPECT_EQ(std::count(uses.begin(), uses.end(), 0), 0) << "every DOF lies in a cell";
    if (order == 2 && m.num_cells() > 1) {  // some node is shared
      EXPECT_GT(std::count_if(uses.begin(), uses.end(), [](int u) { return u >= 2; }), 0);
    }
    // Distinct DOFs: distinct points (no two entities merged).
    std::vector<std::tuple<double, double, double>> p;
    for (Index d = 0; d < dofs.num_dofs(); ++d)
      p.emplace_back(dofs.dof_points()(d, 0), dofs.dof_points()(d, 1), dofs.dof_points()(d, 2));
    std::sort(p.begin(), p.end());
    EXPECT_EQ(std::adjacent_find(p.begin(), p.end()), p.end()) << element.name();
  }
}

TEST_P(DofMap3d, FacetDofsFollowTheFacetElement) {
  const Mesh<3> m = jiggled_box(GetParam());
  for (int order : {1, 2}) {
    const DofMap<3> dofs(m, LagrangeElement<3>(m.cell_type, order));
    const LagrangeElement<2> facet_element(facet_type(m.cell_type), order);
    const LagrangeElement<2> facet_geometry(facet_type(m.cell_type), 1);
    const MatrixX N = facet_geometry.values(facet_element.nodes());
    for (Index f = 0; f < m.num_boundary_facets(); ++f) {
      const std::vector<Index> fd = dofs.facet_dofs(m, f);
      ASSERT_EQ(static_cast<int>(fd.size()), facet_element.num_dofs());
      for (int k = 0; k < facet_element.num_dofs(); ++k) {
        Point<3> x = Point<3>::Zero();
        for (int v = 0; v < facet_geometry.num_dofs(); ++v) x += N(k, v) * m.vertex(m.boundary_facets(f, v));
        EXPECT_LT((x - dofs.dof_points().row(fd[static_cast<std::size_t>(k)]).transpose()).norm(), 1e-12)
            << "facet " << f << " node " << k;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Boxes, DofMap3d,
                         ::testing::Values(BoxCase{CellType::hexahedron, {3, 2, 4}},
                                           BoxCase{CellType::tetrahedron, {3, 2, 4}},
                                           BoxCase{CellType::hexahedron, {1, 1, 1}},
                                           BoxCase{CellType::tetrahedron, {1, 1, 1}}),
                         [](const auto& info) {
                           return to_string(info.param.type) + "_" + std::to_string(info.param.n[0]) + "x" +
                                  std::to_string(info.param.n[1]) + "x" + std::to_string(info.param.n[2]);
                         });

TEST_P(DofMap3d, OutputMeshSharesTheNodesTheDofMapNumbers) {
  // Identity map: the output nodes are the DOF nodes of the same order, each once.
  const Mesh<3> m = jiggled_box(GetParam());
  const fem::DofMap<3> first(m, LagrangeElement<3>(m.cell_type, 1));
  const fem::DofDistribution<3> dist(MPI_COMM_SELF, m, first);
  const mapping::IdentityMap<3> identity;
  for (int order : {1, 2}) {
    const LagrangeElement<3> element(m.cell_type, order);
    const DofMap<3> dofs(m, element);
    const OutputMesh<3> out = make_output_mesh(m, dist, identity, order);
    EXPECT_EQ(out.cell_type, m.cell_type);
    EXPECT_EQ(out.points.rows(), dofs.num_dofs()) << element.name();
    EXPECT_EQ(out.cells.rows(), m.num_cells());
    ASSERT_EQ(out.cells.cols(), element.num_dofs());
    EXPECT_EQ(out.num_tangled_cells, 0);
    for (Index c = 0; c < m.num_cells(); ++c)
      for (int k = 0; k < element.num_dofs(); ++k) {
        const Point<3> x = out.points.row(out.cells(c, k)).transpose();
        ASSERT_LT((x - node_position(m, element, c, k)).norm(), 1e-12) << element.name();
        ASSERT_NEAR(out.map_det(out.cells(c, k)), 1.0, 1e-12);
      }
    // The interpolant of the DOF points' x-coordinates, evaluated at the output nodes.
    const fem::DofDistribution<3> order_dist(MPI_COMM_SELF, m, dofs);
    VectorX relevant(static_cast<Index>(order_dist.relevant_dofs().size()));
    for (std::size_t i = 0; i < order_dist.relevant_dofs().size(); ++i)
      relevant(static_cast<Index>(i)) = dofs.dof_points()(order_dist.relevant_dofs()[i], 0);
    const std::vector<double> values = out.interpolate(dofs, order_dist, relevant);
    ASSERT_EQ(values.size(), static_cast<std::size_t>(out.points.rows()));
    for (Index p = 0; p < out.points.rows(); ++p)
      EXPECT_NEAR(values[static_cast<std::size_t>(p)], out.points(p, 0), 1e-12);
  }
}
