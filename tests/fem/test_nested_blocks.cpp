// Levels above a partitioned base level described per block (base cell): the
// vertex ranges refine_uniformly records are where the blocks' cells first use
// their vertices, and a DofDistribution built from the blocks is the one built
// from every cell's owner (this file also runs under mpiexec -n 2 as
// test_mpi_nested_blocks, where the two differ in how they get there).

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/hierarchy/nested_blocks.hpp"
#include "fem/reference/lagrange_element.hpp"
#include "tests/fem/partial_hierarchy_check.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {

constexpr Index kCellsPerPart = 8;  // a low base level, so that several levels lie above it

Mesh<2> lshape_triangles() {
  const Polygon l = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L");
  return mesh_polygon(l, {.max_edge_length = 0.5});
}

Mesh<2> square_quadrilaterals() {
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "square");
  return split_into_quadrilaterals(mesh_polygon(square, {.max_edge_length = 0.4}));
}

int world_size() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

}  // namespace

TEST(NestedBlocks, VertexRangesAreWhereTheBlocksUseTheirVerticesFirst) {
  for (const Mesh<2>& coarse : {lshape_triangles(), square_quadrilaterals()}) {
    const MeshHierarchy<2> h(coarse, 3);
    const std::vector<LevelPartition> parts = nested_level_partitions(h, 3, kCellsPerPart);
    int levels_with_blocks = 0;
    for (int l = 0; l < h.num_levels(); ++l) {
      const auto& blocks = parts[static_cast<std::size_t>(l)].blocks;
      if (!blocks) continue;
      ++levels_with_blocks;
      const Mesh<2>& mesh = h.levels[static_cast<std::size_t>(l)];
      ASSERT_EQ(blocks->num_cells(), mesh.num_cells());
      // The block of every vertex's first cell, by brute force.
      std::vector<Index> first_block(static_cast<std::size_t>(mesh.num_vertices()), -1);
      for (Index c = 0; c < mesh.num_cells(); ++c)
        for (Index k = 0; k < mesh.cells.cols(); ++k)
          if (Index& b = first_block[static_cast<std::size_t>(mesh.cells(c, k))]; b < 0)
            b = c / blocks->cells_per_block;
      for (Index b = 0; b < blocks->num_blocks(); ++b)
        for (Index v = blocks->first_vertex[static_cast<std::size_t>(b)];
             v < blocks->first_vertex[static_cast<std::size_t>(b + 1)]; ++v)
          ASSERT_EQ(first_block[static_cast<std::size_t>(v)], b) << "level " << l << ", vertex " << v;
      EXPECT_EQ(blocks->first_vertex.front(), 0);
      EXPECT_EQ(blocks->first_vertex.back(), mesh.num_vertices());  // every vertex lies in a cell
      for (Index c = 0; c < mesh.num_cells(); ++c)
        EXPECT_EQ(
            blocks->cell_owner(c),
            nested_partitions(h, 3, kCellsPerPart)[static_cast<std::size_t>(l)][static_cast<std::size_t>(c)]);
    }
    EXPECT_GE(levels_with_blocks, 2);
  }
}

TEST(NestedBlocks, NearBlocksShareABaseVertexWithTheRanksBlocks) {
  const MeshHierarchy<2> h(lshape_triangles(), 2);
  const std::vector<LevelPartition> parts = nested_level_partitions(h, 3, kCellsPerPart);
  const NestedBlocks& blocks = *parts.back().blocks;
  const IndexTable& base = *blocks.base_cells;
  const auto share_vertex = [&](Index a, Index b) {
    for (Index i = 0; i < base.cols(); ++i)
      for (Index j = 0; j < base.cols(); ++j)
        if (base(a, i) == base(b, j)) return true;
    return false;
  };
  for (int rank = 0; rank < 3; ++rank) {
    std::vector<Index> near;
    for (Index a = 0; a < blocks.num_blocks(); ++a)
      for (Index b = 0; b < blocks.num_blocks(); ++b)
        if (blocks.owner[static_cast<std::size_t>(b)] == rank && share_vertex(a, b)) {
          near.push_back(a);
          break;
        }
    EXPECT_EQ(blocks.blocks_near(rank), near) << "rank " << rank;
  }
}

TEST(NestedBlocks, DistributionEqualsTheOneFromListedCellOwners) {
  const int size = world_size();
  for (const Mesh<2>& coarse : {lshape_triangles(), square_quadrilaterals()}) {
    const MeshHierarchy<2> h(coarse, 3);
    const auto listed = nested_partitions(h, size, kCellsPerPart);
    const auto nested = nested_level_partitions(h, size, kCellsPerPart);
    for (int l = 0; l < h.num_levels(); ++l) {
      const auto& blocks = nested[static_cast<std::size_t>(l)].blocks;
      if (!blocks) continue;
      const Mesh<2>& mesh = h.levels[static_cast<std::size_t>(l)];
      for (int order : {1, 2}) {
        const DofMap<2> dofs(mesh, LagrangeElement<2>(mesh.cell_type, order));
        const DofDistribution<2> a(MPI_COMM_WORLD, mesh, dofs, listed[static_cast<std::size_t>(l)]);
        const DofDistribution<2> b(MPI_COMM_WORLD, mesh, dofs, *blocks);
        const std::string where = "level " + std::to_string(l) + ", order " + std::to_string(order);
        EXPECT_EQ(a.local_cells(), b.local_cells()) << where;
        ASSERT_EQ(a.owned_begin(), b.owned_begin()) << where;
        ASSERT_EQ(a.owned_end(), b.owned_end()) << where;
        ASSERT_EQ(a.num_global(), b.num_global()) << where;
        for (Index d = 0; d < dofs.num_dofs(); ++d) {
          ASSERT_EQ(a.owner(d), b.owner(d)) << where << ", DOF " << d;
          ASSERT_EQ(a.global(d), b.global(d)) << where << ", DOF " << d;
        }
        std::vector<PetscInt> ra, ca, rb, cb;
        a.sparsity(mesh, dofs, ra, ca);
        b.sparsity(mesh, dofs, rb, cb);
        EXPECT_EQ(ra, rb) << where;
        EXPECT_EQ(ca, cb) << where;
      }
    }
  }
}

// A hierarchy built for one rank of a partition: on the levels above the base
// only the cells around the rank's are stored, with the numbers, positions and
// boundary facets the whole refinement gives them (every rank of two, three
// and five parts, in one process). Triangles carry an edge numbering from
// level to level, quadrilaterals name their nodes by position.
TEST(PartialRefinement, PresentCellsMatchTheWholeHierarchy) {
  test::expect_partial_levels_match_the_whole_hierarchy<2>(lshape_triangles, 5, kCellsPerPart, {2, 3, 5}, 2);
  test::expect_partial_levels_match_the_whole_hierarchy<2>(square_quadrilaterals, 5, kCellsPerPart, {2, 3, 5},
                                                           2);
}
