#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/mesh/edge_numbering.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/dofs/cell_partition.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {
Polygon lshape() {
  return Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
}

double mesh_area(const Mesh<2>& m) {
  double a = 0;
  for (Index c = 0; c < m.num_cells(); ++c) {
    const Point<2> p = m.vertex(m.cells(c, 0)), q = m.vertex(m.cells(c, 1)), r = m.vertex(m.cells(c, 2));
    const double s = 0.5 * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
    EXPECT_GT(s, 0) << "cell " << c << " is not counter-clockwise";
    a += s;
  }
  return a;
}
}  // namespace

// A finely sampled smooth outline (more nodes than the mesher inserts one by
// one): the mesh covers the polygon, every facet lies on (and between the ends
// of) the edge it is tagged with, and every edge is tagged exactly once.
TEST(PolygonMesher, ManyVertexOutlineCoversAndTagsEveryEdge) {
  const Index n = 6000;
  std::vector<Point<2>> v;
  for (Index i = 0; i < n; ++i) {
    const double t = 2 * M_PI * static_cast<double>(i) / static_cast<double>(n);
    const double r = 1 + 0.1 * std::sin(12 * t);
    v.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  const Polygon poly = Polygon::checked(std::move(v));
  const Mesh<2> m = mesh_polygon(poly);
  EXPECT_NEAR(mesh_area(m), poly.signed_area(), 1e-10);
  ASSERT_EQ(m.num_boundary_facets(), n);  // no size bound: the polygon's own edges
  std::vector<int> count(static_cast<std::size_t>(n), 0);
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    const int e = m.facet_tags[f];
    ASSERT_GE(e, 0);
    ASSERT_LT(e, n);
    ++count[static_cast<std::size_t>(e)];
    const Point<2> a = poly.vertex(e), b = poly.vertex(e + 1);
    const Point<2> p = m.vertex(m.boundary_facets(f, 0)), q = m.vertex(m.boundary_facets(f, 1));
    EXPECT_EQ(p, a) << "facet " << f << " tagged " << e;
    EXPECT_EQ(q, b) << "facet " << f << " tagged " << e;
  }
  EXPECT_TRUE(std::all_of(count.begin(), count.end(), [](int c) { return c == 1; }));
}

TEST(PolygonMesher, CoversPolygonRespectsSizeAndTagsEdges) {
  const Polygon poly = lshape();
  const Mesh<2> m = mesh_polygon(poly, {.max_edge_length = 0.2});
  EXPECT_NEAR(mesh_area(m), 3.0, 1e-12);
  EXPECT_LE(m.max_edge_length(), 0.2 + 1e-12);
  // Every polygon vertex is a mesh vertex.
  for (Index i = 0; i < poly.size(); ++i) {
    bool found = false;
    for (Index v = 0; v < m.num_vertices(); ++v) found |= (m.vertex(v) - poly.vertex(i)).norm() == 0.0;
    EXPECT_TRUE(found) << "polygon vertex " << i;
  }
  // Boundary facets lie on the polygon edge they are tagged with and cover the perimeter.
  double perimeter = 0;
  std::set<int> tags;
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    const int e = m.facet_tags[f];
    tags.insert(e);
    const Point<2> a = poly.vertex(e), b = poly.vertex(e + 1);
    for (int k = 0; k < 2; ++k) {
      const Point<2> p = m.vertex(m.boundary_facets(f, k));
      EXPECT_NEAR((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x(), 0.0, 1e-12);
    }
    perimeter += (m.vertex(m.boundary_facets(f, 1)) - m.vertex(m.boundary_facets(f, 0))).norm();
  }
  EXPECT_NEAR(perimeter, poly.perimeter(), 1e-12);
  EXPECT_EQ(tags.size(), 6u);
}

TEST(UniformRefinement, QuadruplesCellsKeepsAreaAndIsNested) {
  const Mesh<2> coarse = mesh_polygon(lshape(), {.max_edge_length = 0.5});
  const RefinedMesh<2> fine = refine_uniformly(coarse);
  EXPECT_EQ(fine.mesh.num_cells(), 4 * coarse.num_cells());
  EXPECT_EQ(fine.mesh.num_boundary_facets(), 2 * coarse.num_boundary_facets());
  EXPECT_NEAR(mesh_area(fine.mesh), 3.0, 1e-12);
  EXPECT_NEAR(fine.mesh.max_edge_length(), 0.5 * coarse.max_edge_length(), 1e-12);
}

// Child k of every coarse cell c is fine cell 4c + k, and its vertices sit where
// child_reference_vertices(k) says in c's reference cell (what the prolongation
// tabulates once per child).
TEST(UniformRefinement, ChildrenSitAtTheirReferencePositionsInTheParent) {
  for (const bool quads : {false, true}) {
    Mesh<2> coarse = mesh_polygon(lshape(), {.max_edge_length = 0.5});
    if (quads) coarse = split_into_quadrilaterals(coarse);
    const RefinedMesh<2> r = refine_uniformly(coarse);
    const int nv = vertices_per_cell(coarse.cell_type);
    ASSERT_EQ(r.mesh.num_cells(), RefinedMesh<2>::children_per_cell * coarse.num_cells());
    for (Index f = 0; f < r.mesh.num_cells(); ++f) {
      const Index c = RefinedMesh<2>::parent_of(f);
      ASSERT_EQ(c, f / 4);
      const Points<2>& eta = child_reference_vertices<2>(coarse.cell_type, static_cast<int>(f % 4));
      ASSERT_EQ(eta.rows(), nv);
      for (int a = 0; a < nv; ++a) {
        // The parent's straight (bilinear) geometry at eta(a).
        const double s = eta(a, 0), t = eta(a, 1);
        const std::vector<double> w =
            quads ? std::vector<double>{(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t}
                  : std::vector<double>{1 - s - t, s, t};
        Point<2> x = Point<2>::Zero();
        for (int k = 0; k < nv; ++k) x += w[static_cast<std::size_t>(k)] * coarse.vertex(coarse.cells(c, k));
        EXPECT_LE((x - r.mesh.vertex(r.mesh.cells(f, a))).norm(), 1e-14)
            << (quads ? "quad" : "triangle") << " child " << f % 4 << ", vertex " << a;
      }
    }
  }
  EXPECT_THROW(child_reference_vertices<2>(CellType::triangle, 4), warpfem::Error);
}

// Fine vertices are numbered by first use in the fine cells (locality of every DOF-ordered
// loop), and fine_vertex_of_node says where each coarse node went.
TEST(UniformRefinement, NumbersVerticesByFirstUseAndRecordsWhereCoarseNodesWent) {
  for (const bool quads : {false, true}) {
    Mesh<2> coarse = mesh_polygon(lshape(), {.max_edge_length = 0.4});
    if (quads) coarse = split_into_quadrilaterals(coarse);
    const RefinedMesh<2> r = refine_uniformly(coarse);
    const Mesh<2>& fine = r.mesh;
    Index next = 0;
    for (Index c = 0; c < fine.num_cells(); ++c)
      for (Index k = 0; k < fine.cells.cols(); ++k) {
        ASSERT_LE(fine.cells(c, k), next) << "vertex used before all lower indices were";
        if (fine.cells(c, k) == next) ++next;
      }
    EXPECT_EQ(next, fine.num_vertices());
    const EdgeNumbering edges(coarse);
    const Index nv = coarse.num_vertices(), ne = edges.num_edges();
    ASSERT_EQ(r.fine_vertex_of_node.size(),
              static_cast<std::size_t>(nv + ne + (quads ? coarse.num_cells() : 0)));
    for (Index v = 0; v < nv; ++v) EXPECT_EQ(fine.vertex(r.fine_vertex_of_node[v]), coarse.vertex(v));
    for (Index e = 0; e < ne; ++e) {
      const auto& ev = edges.vertices(e);
      EXPECT_EQ(fine.vertex(r.fine_vertex_of_node[nv + e]),
                0.5 * (coarse.vertex(ev[0]) + coarse.vertex(ev[1])));
    }
    if (!quads) {
      EXPECT_NEAR(mesh_area(fine), 3.0, 1e-12);  // mesh_area takes triangles
    }
  }
}

TEST(MeshTables, SizesBeyondThe32BitTablesAreRefusedWithTheirName) {
  EXPECT_EQ(warpfem::checked_table_size(0, "cells"), 0);
  EXPECT_EQ(warpfem::checked_table_size(2147483647, "cells"), 2147483647);
  try {
    warpfem::checked_table_size(Index{2147483648}, "refine_uniformly: fine cells");
    FAIL() << "2^31 entries accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("refine_uniformly: fine cells"), std::string::npos) << e.what();
  }
  EXPECT_THROW(warpfem::checked_table_size(-1, "cells"), Error);
}

TEST(CellPartition, BalancedAndDeterministic) {
  const Mesh<2> m = mesh_polygon(lshape(), {.max_edge_length = 0.1});
  const auto parts = partition_cells(m, 3);
  std::vector<int> count(3, 0);
  for (int p : parts) ++count[p];
  for (int c : count) EXPECT_NEAR(c, m.num_cells() / 3.0, 1.0);
  EXPECT_EQ(parts, partition_cells(m, 3));
}

TEST(CellPartition, NestedPartitionsInheritTheBaseLevelsOwners) {
  const MeshHierarchy<2> h(mesh_polygon(lshape(), {.max_edge_length = 0.5}), 4);
  const int parts = 3;
  const Index min_cells_per_part = 8;
  const auto owners = nested_partitions(h, parts, min_cells_per_part);
  ASSERT_EQ(static_cast<int>(owners.size()), h.num_levels());
  // The base: the coarsest level with at least 8 cells per part; it and every
  // coarser level are cut along the Morton curve.
  int base = 0;
  while (h.levels[static_cast<std::size_t>(base)].num_cells() < min_cells_per_part * parts) ++base;
  ASSERT_LT(base + 2, h.num_levels()) << "the test needs levels finer than the base";
  for (int l = 0; l <= base; ++l)
    EXPECT_EQ(owners[static_cast<std::size_t>(l)],
              partition_cells(h.levels[static_cast<std::size_t>(l)], parts));
  for (int l = base + 1; l < h.num_levels(); ++l) {
    const auto& owner = owners[static_cast<std::size_t>(l)];
    ASSERT_EQ(static_cast<Index>(owner.size()), h.levels[static_cast<std::size_t>(l)].num_cells());
    std::vector<Index> count(parts, 0);
    for (std::size_t c = 0; c < owner.size(); ++c) {
      ASSERT_EQ(owner[c], owners[static_cast<std::size_t>(l - 1)]
                                [static_cast<std::size_t>(RefinedMesh<2>::parent_of(static_cast<Index>(c)))])
          << "level " << l << ", cell " << c;
      ++count[static_cast<std::size_t>(owner[c])];
    }
    // Balanced to one base cell's descendants.
    const double descendants = std::pow(4.0, l - base), mean = static_cast<double>(owner.size()) / parts;
    for (const Index n : count)
      EXPECT_LE(std::abs(static_cast<double>(n) - mean), descendants) << "level " << l;
  }
  for (const auto& owner : nested_partitions(h, 1))
    EXPECT_TRUE(std::all_of(owner.begin(), owner.end(), [](int r) { return r == 0; }));
}

TEST(CellPartition, ChildrenInheritTheirParentsOwner) {
  EXPECT_EQ(inherit_partition({2, 5}), (std::vector<int>{2, 2, 2, 2, 5, 5, 5, 5}));
  EXPECT_TRUE(inherit_partition({}).empty());
}

// Every undirected edge gets one id, in the order the cells first use the edges;
// find() answers for both orientations and only for edges of the mesh.
TEST(EdgeNumbering, NumbersEachEdgeOnceInFirstUseOrder) {
  for (const bool quads : {false, true}) {
    Mesh<2> mesh = mesh_polygon(lshape(), {.max_edge_length = 0.3});
    if (quads) mesh = split_into_quadrilaterals(mesh);
    const EdgeNumbering edges(mesh);
    const auto& local = cell_edges(mesh.cell_type);
    std::set<std::pair<Index, Index>> distinct;
    Index next = 0;
    for (Index c = 0; c < mesh.num_cells(); ++c)
      for (int e = 0; e < static_cast<int>(local.size()); ++e) {
        const Index a = mesh.cells(c, local[e][0]), b = mesh.cells(c, local[e][1]);
        const Index id = edges.cell_edge(c, e);
        ASSERT_LE(id, next) << "edge used before all lower ids were";
        if (id == next) ++next;
        EXPECT_EQ(edges.vertices(id)[0], std::min(a, b));
        EXPECT_EQ(edges.vertices(id)[1], std::max(a, b));
        EXPECT_EQ(edges.find(a, b), id);
        EXPECT_EQ(edges.find(b, a), id);
        distinct.insert({std::min(a, b), std::max(a, b)});
      }
    EXPECT_EQ(edges.num_edges(), static_cast<Index>(distinct.size()));
    // Euler: V − E + F = 1 for a simply connected polygon.
    EXPECT_EQ(mesh.num_vertices() - edges.num_edges() + mesh.num_cells(), 1);
    EXPECT_EQ(edges.find(0, 0), -1);
  }
}

// refine_uniformly can number the fine mesh's edges from the coarse ones: the
// result is exactly EdgeNumbering(fine) (ids, cell table, vertices, find()),
// and its boundary facet table names each fine facet's edge. Two levels deep,
// so the second refinement runs on a derived numbering.
TEST(EdgeNumbering, DerivedFromTheRefinementEqualsTheSearchedOne) {
  const Mesh<2> coarse = mesh_polygon(lshape(), {.max_edge_length = 0.3});
  RefinedMesh<2> once = refine_uniformly(coarse, nullptr, true);
  ASSERT_TRUE(once.fine_edges.has_value());
  RefinedMesh<2> twice = refine_uniformly(once.mesh, &*once.fine_edges, true);
  const RefinedMesh<2> twice_searched = refine_uniformly(once.mesh);
  ASSERT_TRUE(twice.mesh.cells == twice_searched.mesh.cells);
  ASSERT_TRUE(twice.mesh.vertices == twice_searched.mesh.vertices);
  ASSERT_TRUE(twice.mesh.boundary_facets == twice_searched.mesh.boundary_facets);
  EXPECT_EQ(twice.fine_vertex_of_node, twice_searched.fine_vertex_of_node);
  for (const RefinedMesh<2>* r : {&once, &twice}) {
    const Mesh<2>& fine = r->mesh;
    const EdgeNumbering& derived = *r->fine_edges;
    const EdgeNumbering searched(fine);
    ASSERT_EQ(derived.num_edges(), searched.num_edges());
    ASSERT_EQ(derived.num_cells(), fine.num_cells());
    for (Index c = 0; c < fine.num_cells(); ++c)
      for (int e = 0; e < 3; ++e)
        ASSERT_EQ(derived.cell_edge(c, e), searched.cell_edge(c, e)) << c << " " << e;
    for (Index e = 0; e < derived.num_edges(); ++e) EXPECT_EQ(derived.vertices(e), searched.vertices(e));
    for (Index f = 0; f < fine.num_boundary_facets(); ++f) {
      const Index a = fine.boundary_facets(f, 0), b = fine.boundary_facets(f, 1);
      EXPECT_EQ(derived.boundary_facet_edge(f, a, b), searched.find(a, b));
      EXPECT_EQ(derived.find(b, a), searched.find(a, b));
    }
    EXPECT_EQ(derived.find(0, 0), -1);
  }
  // Quadrilaterals keep the searched numbering (none is derived).
  EXPECT_FALSE(refine_uniformly(split_into_quadrilaterals(coarse), nullptr, true).fine_edges.has_value());
  // A numbering of another mesh is refused.
  EXPECT_THROW(refine_uniformly(coarse, &*twice.fine_edges), Error);
}
