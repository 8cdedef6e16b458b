#pragma once
// The levels above a partitioned base level, refined by one rank only around
// its own cells.
//
// refine_uniformly numbers cells hierarchically and vertices and edges by first
// use, so on level base + k the descendants of base cell (block) b are a
// contiguous range of 4^k cells, and the vertices and edges they use first are
// contiguous ranges too. How many each block uses first follows from the base
// level alone (a block's new vertices on level k + 1 are its new vertices and
// the midpoints of its new edges on level k; its new edges the halves of its
// new edges and three inside each of its cells), so every rank knows every
// block's ranges without refining it, and can refine just the blocks it needs
// with the numbers the whole refinement would give.
//
// A rank needs its own blocks and their neighbours (blocks sharing a base
// vertex: their cells hold the rank's DOFs' other couplings); those are the
// Mesh's present_cells. It refines one more ring of blocks, so that every
// vertex of the present cells has its number: a vertex first used by a block
// outside the refined ring can only lie in that ring's outer cells (they keep
// -1 there and are never read).
//
// Tetrahedra (Bey's red refinement), quadrilaterals and hexahedra follow the
// same block layout with 8^k (4^k) cells per block; their nodes are identified
// by their integer coordinates in the base cell instead of by a carried edge
// numbering (refine_by_position.hpp).

#include <vector>

#include "core/mesh/edge_numbering.hpp"
#include "fem/hierarchy/nested_blocks.hpp"

namespace warpfem::fem {

template <int dim>
struct MeshHierarchy;

/// Appends `levels_above` levels to `h`, whose finest level is the partitioned
/// base level (a whole mesh), refined for rank `rank` of
/// `base_owner` (one rank per base cell); appends their NestedBlocks to
/// `blocks`. The new levels are partial meshes (their present_cells: the
/// rank's blocks and their neighbours) with the numbers the whole refinement
/// gives; h.transfers get the parent layout only (no fine_vertex_of_node /
/// first_new_vertex). `base_edges`: the base level's EdgeNumbering if the
/// caller has it (used for triangles only; built here if missing).
template <int dim>
void refine_partially(MeshHierarchy<dim>& h, const std::vector<int>& base_owner, int rank, int levels_above,
                      std::vector<NestedBlocks>& blocks, const EdgeNumbering* base_edges = nullptr);

}  // namespace warpfem::fem
