#pragma once
// The check shared by the partial-refinement tests: a hierarchy built for one
// rank of a partition stores, on the levels above the base, exactly the cells
// of the rank's blocks and their neighbours, with the numbers, positions and
// boundary facets the whole refinement gives them (every rank of every listed
// part count, in one process).

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/edge_numbering.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/hierarchy/nested_blocks.hpp"

namespace warpfem::test {

template <int dim>
void expect_partial_levels_match_the_whole_hierarchy(const std::function<Mesh<dim>()>& coarse,
                                                     int refinements, Index cells_per_part,
                                                     const std::vector<int>& part_counts,
                                                     int min_partial_levels) {
  using fem::HierarchyPartition, fem::LevelPartition, fem::MeshHierarchy;
  const MeshHierarchy<dim> whole(coarse(), refinements);
  for (const int parts : part_counts) {
    const auto whole_parts = fem::nested_level_partitions(whole, parts, cells_per_part);
    for (int rank = 0; rank < parts; ++rank) {
      const MeshHierarchy<dim> h(
          coarse(), refinements,
          HierarchyPartition{.parts = parts, .rank = rank, .min_cells_per_part = cells_per_part});
      ASSERT_EQ(h.num_levels(), whole.num_levels());
      ASSERT_EQ(h.partitions.size(), whole_parts.size());
      int partial_levels = 0;
      for (int l = 0; l < h.num_levels(); ++l) {
        const Mesh<dim>& m = h.levels[static_cast<std::size_t>(l)];
        const Mesh<dim>& w = whole.levels[static_cast<std::size_t>(l)];
        const std::string where = to_string(m.cell_type) + ", " + std::to_string(parts) + " parts, rank " +
                                  std::to_string(rank) + ", level " + std::to_string(l);
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
          for (Index k = 0; k < m.cells.cols(); ++k) {
            ASSERT_EQ(m.cells(c, k), w.cells(c, k)) << where << ", cell " << c;
            // Bitwise: the same sums in the same order as refine_uniformly's.
            ASSERT_EQ(m.vertices.row(m.cells(c, k)), w.vertices.row(w.cells(c, k)))
                << where << ", cell " << c;
          }
        // Stored facets equal the whole level's; the rank's own boundary is stored.
        std::vector<char> mine(static_cast<std::size_t>(m.num_vertices()), 0);
        for (Index c : present)
          if (p.blocks->cell_owner(c) == rank)
            for (Index k = 0; k < m.cells.cols(); ++k) mine[static_cast<std::size_t>(m.cells(c, k))] = 1;
        Index stored = 0;
        for (Index f = 0; f < m.num_boundary_facets(); ++f) {
          EXPECT_EQ(m.facet_tags[static_cast<std::size_t>(f)], w.facet_tags[static_cast<std::size_t>(f)]);
          if (m.has_facet(f)) {
            ++stored;
            ASSERT_EQ(m.boundary_facets.row(f), w.boundary_facets.row(f)) << where << ", facet " << f;
          } else {
            bool own_facet = true;
            for (Index k = 0; k < w.boundary_facets.cols(); ++k)
              own_facet = own_facet && mine[static_cast<std::size_t>(w.boundary_facets(f, k))];
            EXPECT_FALSE(own_facet) << where << ": the rank's own facet " << f << " is missing";
          }
        }
        EXPECT_GT(stored, 0) << where;
        // Whole-mesh algorithms refuse a partial level.
        EXPECT_THROW(EdgeNumbering{m}, Error) << where;
        EXPECT_THROW(refine_uniformly(m), Error) << where;
      }
      EXPECT_GE(partial_levels, min_partial_levels)
          << to_string(whole.levels[0].cell_type) << ", rank " << rank;
    }
  }
}

}  // namespace warpfem::test
