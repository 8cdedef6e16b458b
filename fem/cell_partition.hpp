#pragma once
// Splits the cells of a replicated mesh among MPI ranks: cells are sorted
// along a Morton (Z-order) curve of their centroids and cut into contiguous
// chunks of equal size. Deterministic, so every rank computes the same answer
// without communication, and spatially compact, so interfaces stay short.

#include <vector>

#include "fem/mesh.hpp"

namespace warpfem::fem {

/// Owner rank of every cell.
std::vector<int> partition_cells(const Mesh<2>& mesh, int num_parts);

}  // namespace warpfem::fem
