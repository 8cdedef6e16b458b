#pragma once
// Splits the cells of a replicated mesh among MPI ranks: cells are sorted
// along a Morton (Z-order) curve of their centroids and cut into contiguous
// chunks of equal size. Deterministic, so every rank computes the same answer
// without communication, and spatially compact, so interfaces stay short.

#include <vector>

#include "core/mesh/mesh.hpp"

namespace warpfem::fem {

/// Owner rank of every cell (2D and 3D meshes; whole meshes only).
template <int dim>
std::vector<int> partition_cells(const Mesh<dim>& mesh, int num_parts);

/// Owner rank of every fine cell of a uniform refinement (refine_uniformly: the
/// children of coarse cell c are fine cells n c … n c + n − 1, n =
/// `children_per_cell`, 4 in 2D and 8 in 3D): the owner of the coarse cell it lies in. A partition inherited
/// this way is nested: a rank's fine cells cover exactly its coarse cells, so transfers between the two
/// levels stay on the rank except along the interface.
std::vector<int> inherit_partition(const std::vector<int>& coarse_owner, Index children_per_cell = 4);

}  // namespace warpfem::fem
