#pragma once
// The P1 (cotangent) Laplace solve of thesis §5.1.1 on an auxiliary mesh:
// for each of the n harmonic-coordinate boundary conditions (boundary_data.hpp),
// the discrete harmonic function with those values at the boundary vertices.
// Assembled into a PETSc sequential AIJ matrix of the interior unknowns and
// solved with one KSP (options prefix "harmonic_", default: Cholesky with
// nested-dissection ordering) for all n right-hand sides.

#include <vector>

#include "core/types.hpp"
#include "mapping/harmonic/boundary_data.hpp"
#include "mapping/harmonic/triangle_mesh.hpp"

namespace warpfem::mapping {

/// nv x n matrix: column k holds λ_k at the mesh vertices. Boundary rows equal
/// boundary_weights() exactly. Throws warpfem::Error if PETSc fails.
MatrixX p1_harmonic_coordinates(const TriangleMesh& mesh, const std::vector<EdgeSpeed>& speeds, Index n);

}  // namespace warpfem::mapping
