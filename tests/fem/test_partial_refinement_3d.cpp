// A tetrahedral hierarchy built for one rank of a partition: on the levels
// above the base only the cells around the rank's are stored, with the
// numbers, positions and boundary facets the whole refinement gives them.
// Hexahedral hierarchies built for a partition stay whole.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/hierarchy/nested_blocks.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {

// Skewed box: no coordinate is a multiple of another, so a midpoint in the
// wrong place shows in the positions.
Mesh<3> box(CellType type) {
  return structured_box_mesh(Point<3>(-0.3, 0.1, 0.7), Point<3>(1.1, 0.9, 1.9), {3, 2, 3}, type);
}

}  // namespace

TEST(PartialRefinement3d, PresentTetrahedraMatchTheWholeHierarchy) {
  constexpr int refinements = 3;
  constexpr Index cells_per_part = 60;  // base level 1 for two and three parts: two partial levels
  const MeshHierarchy<3> whole(box(CellType::tetrahedron), refinements);
  for (const int parts : {2, 3}) {
    const auto whole_parts = nested_level_partitions(whole, parts, cells_per_part);
    for (int rank = 0; rank < parts; ++rank) {
      const MeshHierarchy<3> h(
          box(CellType::tetrahedron), refinements,
          HierarchyPartition{.parts = parts, .rank = rank, .min_cells_per_part = cells_per_part});
      ASSERT_EQ(h.num_levels(), whole.num_levels());
      ASSERT_EQ(h.partitions.size(), whole_parts.size());
      int partial_levels = 0;
      for (int l = 0; l < h.num_levels(); ++l) {
        const Mesh<3>& m = h.levels[static_cast<std::size_t>(l)];
        const Mesh<3>& w = whole.levels[static_cast<std::size_t>(l)];
        const std::string where =
            std::to_string(parts) + " parts, rank " + std::to_string(rank) + ", level " + std::to_string(l);
        ASSERT_EQ(m.num_cells(), w.num_cells()) << where;
        ASSERT_EQ(m.num_vertices(), w.num_vertices()) << where;
        ASSERT_EQ(m.num_boundary_facets(), w.num_boundary_facets()) << where;
        const LevelPartition& p = h.partitions[static_cast<std::size_t>(l)];
        const LevelPartition& wp = whole_parts[static_cast<std::size_t>(l)];
        EXPECT_EQ(p.cell_owner, wp.cell_owner) << where;
        ASSERT_EQ(p.blocks.has_value(), wp.blocks.has_value()) << where;
        if (p.blocks) {
          EXPECT_EQ(p.blocks->first_vertex, wp.blocks->first_vertex) << where;
          EXPECT_EQ(p.blocks->cells_per_block, wp.blocks->cells_per_block) << where;
          EXPECT_EQ(p.blocks->owner, wp.blocks->owner) << where;
        }
        if (!m.partial) {
          EXPECT_TRUE(m.cells == w.cells) << where;
          EXPECT_TRUE(m.vertices == w.vertices) << where;
          continue;
        }
        ++partial_levels;
        // Present: exactly the cells of the rank's blocks and their neighbours.
        std::vector<Index> expected, present;
        for (Index b : p.blocks->blocks_near(rank))
          for (Index c = b * p.blocks->cells_per_block; c < (b + 1) * p.blocks->cells_per_block; ++c)
            expected.push_back(c);
        for (const auto& [first, last] : m.cell_ranges())
          for (Index c = first; c < last; ++c) present.push_back(c);
        EXPECT_EQ(present, expected) << where;
        EXPECT_LT(static_cast<Index>(present.size()), m.num_cells()) << where;  // something was left out
        for (Index c : present)
          for (Index k = 0; k < 4; ++k) {
            ASSERT_EQ(m.cells(c, k), w.cells(c, k)) << where << ", cell " << c;
            ASSERT_EQ(m.vertices.row(m.cells(c, k)), w.vertices.row(w.cells(c, k)))
                << where << ", cell " << c;
          }
        // Stored facets equal the whole level's; the rank's own boundary is stored.
        std::vector<char> mine(static_cast<std::size_t>(m.num_vertices()), 0);
        for (Index c : present)
          if (p.blocks->cell_owner(c) == rank)
            for (Index k = 0; k < 4; ++k) mine[static_cast<std::size_t>(m.cells(c, k))] = 1;
        Index stored = 0;
        for (Index f = 0; f < m.num_boundary_facets(); ++f) {
          EXPECT_EQ(m.facet_tags[static_cast<std::size_t>(f)], w.facet_tags[static_cast<std::size_t>(f)]);
          if (m.has_facet(f)) {
            ++stored;
            ASSERT_EQ(m.boundary_facets.row(f), w.boundary_facets.row(f)) << where << ", facet " << f;
          } else {
            EXPECT_FALSE(mine[static_cast<std::size_t>(w.boundary_facets(f, 0))] &&
                         mine[static_cast<std::size_t>(w.boundary_facets(f, 1))] &&
                         mine[static_cast<std::size_t>(w.boundary_facets(f, 2))])
                << where << ": the rank's own facet " << f << " is missing";
          }
        }
        EXPECT_GT(stored, 0) << where;
        EXPECT_THROW(refine_uniformly(m), Error);  // whole-mesh algorithms refuse a partial level
      }
      EXPECT_EQ(partial_levels, 2) << "rank " << rank;
    }
  }
}

TEST(PartialRefinement3d, HexahedralHierarchiesForAPartitionAreWhole) {
  const MeshHierarchy<3> whole(box(CellType::hexahedron), 2);
  const MeshHierarchy<3> h(box(CellType::hexahedron), 2,
                           HierarchyPartition{.parts = 2, .rank = 1, .min_cells_per_part = 4});
  ASSERT_EQ(h.num_levels(), whole.num_levels());
  const auto whole_parts = nested_level_partitions(whole, 2, 4);
  for (int l = 0; l < h.num_levels(); ++l) {
    const std::size_t i = static_cast<std::size_t>(l);
    EXPECT_FALSE(h.levels[i].partial) << "level " << l;
    EXPECT_TRUE(h.levels[i].cells == whole.levels[i].cells) << "level " << l;
    EXPECT_EQ(h.partitions[i].cell_owner, whole_parts[i].cell_owner) << "level " << l;
    EXPECT_EQ(h.partitions[i].blocks.has_value(), l > 0) << "level " << l;  // base: level 0 (18 cells)
    if (h.partitions[i].blocks) {
      EXPECT_EQ(h.partitions[i].blocks->first_vertex, whole_parts[i].blocks->first_vertex) << "level " << l;
    }
  }
}
