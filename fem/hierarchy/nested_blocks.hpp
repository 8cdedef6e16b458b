#pragma once
// The partition of a refined level that descends from a partitioned base level.
//
// refine_uniformly orders cells hierarchically (the children of coarse cell c
// are fine cells 2^dim c … 2^dim c + 2^dim − 1) and numbers vertices by first
// use in that order. On level base + k, the descendants of base cell b are
// therefore the contiguous cells [b 2^(dim k), (b + 1) 2^(dim k)), and the
// vertices they use first are contiguous too. A partition inherited from the base level (every cell takes
// the owner of its base cell) is then described per *block* (base cell)
// instead of per cell: the owner of every cell, the rank's cells and, for
// vertex DOFs, the owner and PETSc number of every DOF follow from a few
// numbers per block, without scanning the level's cells.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh/mesh.hpp"

namespace warpfem::fem {

template <int dim>
struct MeshHierarchy;

struct NestedBlocks {
  /// The cells of the partitioned base level (their shared vertices give the
  /// blocks next to a rank's); any dimension.
  const IndexTable* base_cells = nullptr;
  /// Owner rank of every base cell (block).
  std::vector<int> owner;
  /// 2^(dim k) for a level k refinements above the base.
  Index cells_per_block = 1;
  /// first_vertex[b] … first_vertex[b + 1]: the vertices block b's cells use
  /// first (blocks + 1 entries); vertices from first_vertex.back() on lie in no cell.
  std::vector<TableIndex> first_vertex;

  Index num_blocks() const { return static_cast<Index>(owner.size()); }
  Index num_cells() const { return num_blocks() * cells_per_block; }
  int cell_owner(Index cell) const { return owner[static_cast<std::size_t>(cell / cells_per_block)]; }
  /// Blocks whose cells can contain a vertex that one of `rank`'s blocks uses
  /// first: its own and those sharing a base vertex with one of them, in order.
  std::vector<Index> blocks_near(int rank) const;
};

/// Base cells sharing a vertex with a cell of `seed` (masks over the base cells;
/// the seed's own cells included).
std::vector<char> blocks_sharing_a_vertex(const IndexTable& base_cells, const std::vector<char>& seed);

/// The blocks one rank refines on the partial levels above a partitioned base
/// level: its own and their neighbours (`near`: their cells are the levels'
/// present cells) and one more ring (`refined`: so that every vertex of a
/// present cell gets its number), as masks and as increasing lists, and the
/// refined blocks as runs [b0, b1) of consecutive blocks (the arrays they
/// write are populated run by run, one system call each: a single block's
/// share is below prefault()'s megabyte and would be faulted page by page).
struct RefinedRing {
  std::vector<char> near, refined;
  std::vector<Index> near_blocks, refined_blocks;
  std::vector<std::array<Index, 2>> refined_runs;
};
RefinedRing refined_ring(const IndexTable& base_cells, const std::vector<int>& base_owner, int rank);

/// Appends the partial level `fine` (`cells_per_block` cells per block, block
/// b's vertices from first_vertex[b]) to `h`, whose level `base_level` is the
/// partitioned base: its present cells are those of ring.near_blocks, its
/// NestedBlocks go to `blocks`, its transfer records the parent layout only.
template <int dim>
void append_partial_level(MeshHierarchy<dim>& h, int base_level, Mesh<dim> fine, const RefinedRing& ring,
                          const std::vector<int>& base_owner, Index cells_per_block,
                          const std::vector<TableIndex>& first_vertex, std::vector<NestedBlocks>& blocks);

/// first[b] = count[0] + … + count[b - 1] (blocks + 1 entries): where each
/// block's range of vertices (or edges) starts; an error naming `what` when
/// a sum does not fit a TableIndex.
std::vector<TableIndex> block_offsets(const std::vector<Index>& count, const std::string& what);

/// The cells of `blocks` (increasing) on a level of `cells_per_block` cells per
/// block, as ranges [first, last), consecutive blocks merged.
std::vector<std::array<Index, 2>> block_cell_ranges(const std::vector<Index>& blocks, Index cells_per_block);

/// The owners of one level's cells: explicit (one rank per cell, the same on
/// every rank) on and below the partitioned base level, as blocks above it.
struct LevelPartition {
  std::vector<int> cell_owner;
  std::optional<NestedBlocks> blocks;
};

/// The blocks of level `level` of `h` over the partitioned level `base` < `level`
/// (`base_owner`: one rank per cell of level `base`).
template <int dim>
NestedBlocks nested_blocks(const MeshHierarchy<dim>& h, int base, int level, std::vector<int> base_owner);

}  // namespace warpfem::fem
