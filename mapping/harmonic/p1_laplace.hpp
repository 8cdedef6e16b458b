#pragma once
// The P1 (cotangent) Laplace solve of thesis §5.1.1 on an auxiliary mesh:
// for each of the n harmonic-coordinate boundary conditions (boundary_data.hpp),
// the discrete harmonic function with those values at the boundary vertices.
// Solved for all n right-hand sides with one factorisation (p1_dirichlet.hpp).

#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"
#include "core/types.hpp"
#include "mapping/harmonic/boundary_data.hpp"

namespace warpfem::mapping {

/// The auxiliary mesh: CGAL's constrained Delaunay mesh of `domain` with
/// edges at most `max_edge_length` (and angles ≥ ~20.7°), every edge of ∂Ω
/// first split into equal pieces no longer than max_edge_length, so every
/// polygon vertex is a mesh vertex. Throws warpfem::Error if the mesh would
/// exceed `max_triangles`.
Mesh<2> auxiliary_mesh(const Polygon& domain, Real max_edge_length, Index max_triangles = 2'000'000);

/// nv x n matrix: column k holds λ_k at the vertices of `mesh`, a triangle mesh
/// of `domain`. Boundary rows equal boundary_weights() exactly. Throws
/// warpfem::Error if PETSc fails.
MatrixX p1_harmonic_coordinates(const Mesh<2>& mesh, const Polygon& domain,
                                const std::vector<EdgeSpeed>& speeds, Index n);

}  // namespace warpfem::mapping
