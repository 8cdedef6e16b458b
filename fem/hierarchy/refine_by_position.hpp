#pragma once
// Partial refinement of tetrahedral, quadrilateral and hexahedral levels, with
// every node named by its integer coordinates in its base cell (the file
// comment of partial_refinement.hpp says what partial refinement is).
//
// A node of level base + k (a coarse vertex, edge midpoint, face centre or
// cell centre) sits at integer coordinates on the 2^k lattice of its base
// cell: barycentric for tetrahedra, tensor-product for quadrilaterals and
// hexahedra. Every cell computes them from its place in the hierarchy alone
// (the digits of its number within its block), so no edge or face numbering
// is carried from level to level. A node is numbered by the first base cell
// around the sub-entity (vertex, edge, face, cell) holding it: that block's
// descendants use it first. Neighbouring blocks look the number up under the
// node's coordinates converted to the owner's frame through the weights of
// the shared sub-entity's vertices (barycentric coordinates, or products of
// the tensor coordinates), which do not depend on the cell that computes them.

#include <vector>

#include "fem/hierarchy/nested_blocks.hpp"

namespace warpfem::fem {

template <int dim>
struct MeshHierarchy;

/// refine_partially for a whole base level of tetrahedra (dim 3),
/// quadrilaterals (dim 2) or hexahedra (dim 3).
template <int dim>
void refine_by_position(MeshHierarchy<dim>& h, const std::vector<int>& base_owner, int rank, int levels_above,
                        std::vector<NestedBlocks>& blocks);

}  // namespace warpfem::fem
