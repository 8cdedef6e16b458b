#pragma once
// Face-to-face adjacency of a simplicial mesh, for algorithms that walk from
// cell to cell (e.g. a Newton iteration kept inside the mesh). Built on demand
// rather than stored in every Mesh.

#include "core/mesh/mesh.hpp"

namespace warpfem {

/// cells x (dim + 1) table: entry (c, i) is the cell across the facet of cell c
/// opposite its local vertex i, or -1 where that facet is on the boundary.
/// Needs a whole mesh of triangles (dim 2) or tetrahedra (dim 3).
template <int dim>
IndexTable simplex_neighbours(const Mesh<dim>& mesh);

}  // namespace warpfem
