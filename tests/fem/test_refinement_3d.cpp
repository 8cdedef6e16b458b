// Uniform refinement of hexahedral and tetrahedral meshes and 3D hierarchies:
// children tile their parents exactly (volume, vertices at their reference
// positions, positive orientation), nested structured hierarchies have the
// counts of the finer grids, boundary facets keep their tags and stay outward
// and conforming, Bey's rule keeps the tetrahedra's shape bounded, and the
// per-child prolongation tables reproduce linear and quadratic functions.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "core/error.hpp"
#include "core/mesh/quadrature.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/reference/lagrange_element.hpp"
#include "multigrid/prolongation.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {

const Point<3> lo(-1.0, 0.5, 2.0), hi(2.0, 1.25, 3.5);

/// The vertices of cell c as rows.
Points<3> cell_points(const Mesh<3>& m, Index c) {
  Points<3> x(m.cells.cols(), 3);
  for (Index v = 0; v < m.cells.cols(); ++v) x.row(v) = m.vertices.row(m.cells(c, v));
  return x;
}

/// Volume of cell c by quadrature of det J (exact for P1/Q1 geometry); fails
/// the test if det J <= 0 anywhere.
double cell_volume(const Mesh<3>& m, Index c) {
  const LagrangeElement<3> geo(m.cell_type, 1);
  const auto rule = cell_quadrature<3>(m.cell_type, 3);
  const auto grad = geo.gradients(rule.points);
  const Points<3> x = cell_points(m, c);
  double v = 0;
  for (Index q = 0; q < rule.points.rows(); ++q) {
    Eigen::Matrix3d J;
    for (int d = 0; d < 3; ++d) J.col(d) = (grad[static_cast<std::size_t>(d)].row(q) * x).transpose();
    EXPECT_GT(J.determinant(), 0) << "cell " << c << " is not positively oriented";
    v += rule.weights(q) * J.determinant();
  }
  return v;
}

/// A box mesh with its interior vertices moved (cells stay positive, hexahedra get non-planar faces).
Mesh<3> distorted_box(CellType type) {
  Mesh<3> m = structured_box_mesh(lo, hi, {3, 2, 2}, type);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.12, 0.12);
  const Point<3> h = (hi - lo).cwiseQuotient(Point<3>(3, 2, 2));
  for (Index v = 0; v < m.num_vertices(); ++v) {
    const Point<3> x = m.vertex(v);
    for (int d = 0; d < 3; ++d)
      if (x(d) > lo(d) + 1e-12 && x(d) < hi(d) - 1e-12) m.vertices(v, d) += u(rng) * h(d);
  }
  return m;
}

/// Longest edge over inradius, scaled so that the regular tetrahedron has 1.
double aspect_ratio(const Points<3>& x) {
  double longest = 0, area = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) longest = std::max(longest, (x.row(i) - x.row(j)).norm());
  for (const auto& f : cell_faces(CellType::tetrahedron)) {
    const Eigen::Vector3d a = x.row(f[1]) - x.row(f[0]), b = x.row(f[2]) - x.row(f[0]);
    area += 0.5 * a.cross(b).norm();
  }
  const Eigen::Vector3d a = x.row(1) - x.row(0), b = x.row(2) - x.row(0), c = x.row(3) - x.row(0);
  const double inradius = std::abs(a.dot(b.cross(c))) / 2.0 / area;  // 3 V / area
  return longest / (2.0 * std::sqrt(6.0) * inradius);
}

/// Sorted edge lengths over the longest: equal for similar tetrahedra.
std::array<long, 6> shape_key(const Points<3>& x) {
  std::array<double, 6> e{};
  int k = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) e[static_cast<std::size_t>(k++)] = (x.row(i) - x.row(j)).norm();
  std::sort(e.begin(), e.end());
  std::array<long, 6> key{};
  for (std::size_t i = 0; i < 6; ++i) key[i] = std::lround(1e8 * e[i] / e[5]);
  return key;
}

std::vector<TableIndex> sorted_row(const IndexTable& t, Index r) {
  std::vector<TableIndex> v(t.row(r).data(), t.row(r).data() + t.cols());
  std::sort(v.begin(), v.end());
  return v;
}

class Refinement3d : public ::testing::TestWithParam<CellType> {};

}  // namespace

TEST_P(Refinement3d, ChildrenTileTheirParentExactly) {
  const Mesh<3> coarse = distorted_box(GetParam());
  const RefinedMesh<3> r = refine_uniformly(coarse);
  const Mesh<3>& fine = r.mesh;
  ASSERT_EQ(fine.num_cells(), 8 * coarse.num_cells());
  const LagrangeElement<3> geo(coarse.cell_type, 1);
  double worst_volume = 0, worst_position = 0;
  for (Index c = 0; c < coarse.num_cells(); ++c) {
    const double parent = cell_volume(coarse, c);
    double children = 0;
    const Points<3> x = cell_points(coarse, c);
    for (int k = 0; k < 8; ++k) {
      const Index f = 8 * c + k;
      ASSERT_EQ(RefinedMesh<3>::parent_of(f), c);
      children += cell_volume(fine, f);
      // The child's vertices are the parent's geometry at child_reference_vertices(k).
      const Points<3> at = geo.values(child_reference_vertices<3>(coarse.cell_type, k)) * x;
      worst_position = std::max(worst_position, (at - cell_points(fine, f)).cwiseAbs().maxCoeff());
    }
    worst_volume = std::max(worst_volume, std::abs(children - parent) / parent);
  }
  EXPECT_LT(worst_volume, 1e-13);
  EXPECT_LT(worst_position, 1e-14);
  // Where the coarse nodes went: vertices stay, edge midpoints are halfway.
  const EdgeNumbering edges(coarse);
  for (Index v = 0; v < coarse.num_vertices(); ++v)
    EXPECT_EQ(fine.vertex(r.fine_vertex_of_node[static_cast<std::size_t>(v)]), coarse.vertex(v));
  for (Index e = 0; e < edges.num_edges(); ++e) {
    const auto& ev = edges.vertices(e);
    const Point<3> mid = 0.5 * (coarse.vertex(ev[0]) + coarse.vertex(ev[1]));
    EXPECT_EQ(fine.vertex(r.fine_vertex_of_node[static_cast<std::size_t>(coarse.num_vertices() + e)]), mid);
  }
  // The children of c use first exactly the vertices first_new_vertex[c] … [c + 1].
  std::vector<char> seen(static_cast<std::size_t>(fine.num_vertices()), 0);
  for (Index c = 0; c < coarse.num_cells(); ++c)
    for (Index f = 8 * c; f < 8 * c + 8; ++f)
      for (Index k = 0; k < fine.cells.cols(); ++k) {
        const TableIndex v = fine.cells(f, k);
        if (seen[static_cast<std::size_t>(v)]) continue;
        seen[static_cast<std::size_t>(v)] = 1;
        EXPECT_GE(v, r.first_new_vertex[static_cast<std::size_t>(c)]);
        EXPECT_LT(v, r.first_new_vertex[static_cast<std::size_t>(c) + 1]);
      }
}

// structured_box_mesh refined l times has the vertices, cells and boundary
// facets of the box mesh with 2^l times the cells per direction, boundary
// facets on their tagged faces, outward, and exactly the fine mesh's boundary.
TEST_P(Refinement3d, NestedStructuredHierarchyHasTheFinerGridsCountsAndTags) {
  const CellType type = GetParam();
  const std::array<int, 3> n{2, 3, 1};
  const MeshHierarchy<3> h(structured_box_mesh(lo, hi, n, type), 3);
  ASSERT_EQ(h.num_levels(), 4);
  const Index per_box = type == CellType::tetrahedron ? 6 : 1,
              per_face = type == CellType::tetrahedron ? 2 : 1;
  for (int l = 0; l < h.num_levels(); ++l) {
    const Mesh<3>& m = h.levels[static_cast<std::size_t>(l)];
    const Index s = Index{1} << l, nx = n[0] * s, ny = n[1] * s, nz = n[2] * s;
    EXPECT_EQ(m.num_vertices(), (nx + 1) * (ny + 1) * (nz + 1)) << "level " << l;
    EXPECT_EQ(m.num_cells(), per_box * nx * ny * nz) << "level " << l;
    EXPECT_EQ(m.num_boundary_facets(), 2 * per_face * (nx * ny + ny * nz + nx * nz)) << "level " << l;
    // Every vertex is a point of the finer grid.
    const Point<3> step = (hi - lo).cwiseQuotient(Point<3>(double(nx), double(ny), double(nz)));
    for (Index v = 0; v < m.num_vertices(); ++v)
      for (int d = 0; d < 3; ++d) {
        const double t = (m.vertices(v, d) - lo(d)) / step(d);
        ASSERT_NEAR(t, std::round(t), 1e-9) << "level " << l << " vertex " << v;
      }
    if (l == 0) continue;
    // Tags: each fine facet keeps its parent's, lies on that box face and points out of it.
    const Mesh<3>& coarse = h.levels[static_cast<std::size_t>(l - 1)];
    for (Index f = 0; f < m.num_boundary_facets(); ++f) {
      const int tag = m.facet_tags[static_cast<std::size_t>(f)];
      ASSERT_EQ(tag, coarse.facet_tags[static_cast<std::size_t>(f / 4)]);
      const int axis = tag / 2;
      const double plane = tag % 2 ? hi(axis) : lo(axis);
      for (Index k = 0; k < m.boundary_facets.cols(); ++k)
        ASSERT_NEAR(m.vertices(m.boundary_facets(f, k), axis), plane, 1e-12);
      const Point<3> a = m.vertex(m.boundary_facets(f, 0)), b = m.vertex(m.boundary_facets(f, 1)),
                     c = m.vertex(m.boundary_facets(f, 2));
      const double outward = (b - a).cross(c - a)(axis) * (tag % 2 ? 1 : -1);
      EXPECT_GT(outward, 0) << "level " << l << " facet " << f;
    }
    // The refined facets are the fine mesh's boundary, nothing more or less.
    std::set<std::vector<TableIndex>> refined, found;
    const IndexTable boundary = find_boundary_facets(m);
    for (Index f = 0; f < m.num_boundary_facets(); ++f) refined.insert(sorted_row(m.boundary_facets, f));
    for (Index f = 0; f < boundary.rows(); ++f) found.insert(sorted_row(boundary, f));
    EXPECT_EQ(refined, found) << "level " << l;
  }
}

INSTANTIATE_TEST_SUITE_P(Cells, Refinement3d, ::testing::Values(CellType::hexahedron, CellType::tetrahedron),
                         [](const auto& info) { return to_string(info.param); });

// Bey's rule: the descendants of one tetrahedron fall into at most three
// similarity classes, so the worst aspect ratio stays within a fixed factor of
// the initial one however often the mesh is refined.
TEST(TetrahedronRefinement, ShapeQualityStaysBoundedOverFiveLevels) {
  struct Case {
    const char* name;
    std::array<Point<3>, 4> x;
  };
  const std::vector<Case> cases = {
      {"reference", {Point<3>(0, 0, 0), Point<3>(1, 0, 0), Point<3>(0, 1, 0), Point<3>(0, 0, 1)}},
      {"kuhn", {Point<3>(0, 0, 0), Point<3>(1, 0, 0), Point<3>(1, 1, 0), Point<3>(1, 1, 1)}},
      {"flat", {Point<3>(0, 0, 0), Point<3>(1, 0.1, 0), Point<3>(0.3, 1, 0.05), Point<3>(0.4, 0.2, 0.3)}}};
  for (const Case& c : cases) {
    Mesh<3> one;
    one.cell_type = CellType::tetrahedron;
    one.vertices.resize(4, 3);
    for (int v = 0; v < 4; ++v) one.vertices.row(v) = c.x[static_cast<std::size_t>(v)].transpose();
    one.cells.resize(1, 4);
    one.cells << 0, 1, 2, 3;
    one.boundary_facets = find_boundary_facets(one);
    one.facet_tags.assign(4, 0);
    const double initial = aspect_ratio(cell_points(one, 0));
    const MeshHierarchy<3> h(std::move(one), 5);
    const Mesh<3>& fine = h.finest();
    ASSERT_EQ(fine.num_cells(), 32768);
    double worst = 0, volume = 0;
    std::set<std::array<long, 6>> classes;
    for (Index f = 0; f < fine.num_cells(); ++f) {
      const Points<3> x = cell_points(fine, f);
      worst = std::max(worst, aspect_ratio(x));
      classes.insert(shape_key(x));
      volume += cell_volume(fine, f);
    }
    EXPECT_NEAR(volume, cell_volume(h.levels[0], 0), 1e-13);
    std::printf(
        "[ tet quality ] %s: worst aspect ratio %.3f initially, %.3f after 5 levels (%.2fx), %zu shapes\n",
        c.name, initial, worst, worst / initial, classes.size());
    EXPECT_LE(classes.size(), 3u) << c.name;
    EXPECT_LE(worst, 2.5 * initial) << c.name;
  }
}

// order_for_refinement: whatever order a mesher gives the vertices of a flat
// tetrahedron in, the reordered cell keeps its orientation, Bey's diagonal
// m02–m13 is the shortest, and the refinements reach the same worst shape,
// which is no worse than the given order's.
TEST(TetrahedronRefinement, ShortestDiagonalOrderIsTheSameForEveryVertexOrder) {
  const std::array<Point<3>, 4> x = {Point<3>(0, 0, 0), Point<3>(1, 0.1, 0), Point<3>(0.3, 1, 0.05),
                                     Point<3>(0.4, 0.2, 0.3)};
  const auto worst_after = [](Mesh<3> m, int levels) {
    const MeshHierarchy<3> h(std::move(m), levels);
    double worst = 0;
    for (Index f = 0; f < h.finest().num_cells(); ++f)
      worst = std::max(worst, aspect_ratio(cell_points(h.finest(), f)));
    return worst;
  };
  const auto signed_volume = [](const Mesh<3>& m) {
    const Points<3> p = cell_points(m, 0);
    return (p.row(1) - p.row(0)).dot((p.row(2) - p.row(0)).cross(p.row(3) - p.row(0))) / 6;
  };
  std::array<int, 4> order = {0, 1, 2, 3};
  std::vector<double> ordered;
  do {
    Mesh<3> one;
    one.cell_type = CellType::tetrahedron;
    one.vertices.resize(4, 3);
    for (int v = 0; v < 4; ++v) one.vertices.row(v) = x[static_cast<std::size_t>(v)].transpose();
    one.cells.resize(1, 4);
    for (int v = 0; v < 4; ++v) one.cells(0, v) = order[static_cast<std::size_t>(v)];
    if (signed_volume(one) < 0) continue;  // the 12 positively oriented orders
    one.boundary_facets = find_boundary_facets(one);
    one.facet_tags.assign(4, 0);
    const double given = worst_after(one, 3);
    order_for_refinement(one);
    EXPECT_GT(signed_volume(one), 0);
    const Points<3> p = cell_points(one, 0);
    const auto diagonal = [&](int a, int b, int c, int d) {
      return (p.row(a) + p.row(b) - p.row(c) - p.row(d)).norm();
    };
    EXPECT_LE(diagonal(0, 2, 1, 3), diagonal(0, 1, 2, 3));
    EXPECT_LE(diagonal(0, 2, 1, 3), diagonal(0, 3, 1, 2));
    ordered.push_back(worst_after(one, 3));
    EXPECT_LE(ordered.back(), given + 1e-12);
  } while (std::next_permutation(order.begin(), order.end()));
  ASSERT_EQ(ordered.size(), 12u);
  for (const double w : ordered) EXPECT_NEAR(w, ordered.front(), 1e-12);
  std::printf("[ tet quality ] flat, shortest diagonal first: worst aspect ratio %.3f after 3 levels\n",
              ordered.front());
}

TEST(MeshHierarchy3d, ChildrenOutsideTheTableAreRefused) {
  EXPECT_THROW(child_reference_vertices<3>(CellType::tetrahedron, 8), Error);
  EXPECT_THROW(child_reference_vertices<3>(CellType::triangle, 0), Error);
}

// P(i, j) = φ_j^coarse(x_i^fine) through the per-child tables: on an affine box
// hierarchy the prolongation of the coarse interpolant of a polynomial in the
// space is the fine interpolant (linear for order 1, quadratic for order 2),
// and every row sums to one.
TEST(Prolongation3d, ChildTablesReproducePolynomialsOfTheSpace) {
  const auto u = [](const Point<3>& x, int order) {
    const double linear = 1.0 + 2.0 * x(0) - 0.5 * x(1) + 0.75 * x(2);
    return order == 1 ? linear : linear + x(0) * x(0) - 1.5 * x(1) * x(2) + 0.5 * x(2) * x(2) + x(0) * x(1);
  };
  for (const CellType type : {CellType::hexahedron, CellType::tetrahedron})
    for (const int order : {1, 2}) {
      const MeshHierarchy<3> h(structured_box_mesh(lo, hi, {2, 1, 2}, type), 1);
      const Mesh<3>& coarse = h.levels[0];
      const Mesh<3>& fine = h.levels[1];
      const LagrangeElement<3> element(type, order), geo(type, 1);
      const std::vector<MatrixX> tables = multigrid::child_prolongation_tables(element);
      ASSERT_EQ(tables.size(), 8u);
      const MatrixX at_nodes = geo.values(element.nodes());
      double worst = 0, worst_sum = 0;
      for (Index f = 0; f < fine.num_cells(); ++f) {
        const Index c = RefinedMesh<3>::parent_of(f);
        const Points<3> xc = at_nodes * cell_points(coarse, c), xf = at_nodes * cell_points(fine, f);
        VectorX uc(element.num_dofs());
        for (int j = 0; j < element.num_dofs(); ++j) uc(j) = u(xc.row(j).transpose(), order);
        const MatrixX& table = tables[static_cast<std::size_t>(f % 8)];
        const VectorX uf = table * uc;
        for (int i = 0; i < element.num_dofs(); ++i) {
          worst = std::max(worst, std::abs(uf(i) - u(xf.row(i).transpose(), order)));
          worst_sum = std::max(worst_sum, std::abs(table.row(i).sum() - 1.0));
        }
      }
      EXPECT_LT(worst, 1e-12) << to_string(type) << " order " << order;
      EXPECT_LT(worst_sum, 1e-13) << to_string(type) << " order " << order;
    }
}
