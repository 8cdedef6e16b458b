#pragma once
// The discrete harmonic extension of Dirichlet data on a simplex mesh: P1
// stiffness matrix of the free vertices (cotangent weights in 2D, their
// tetrahedral analogue in 3D) in a PETSc sequential AIJ matrix, factored once
// by one KSP (options prefix "harmonic_", default: Cholesky with
// nested-dissection ordering) and solved for every column of the data.

#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/types.hpp"

namespace warpfem::mapping {

/// `values` is nv x m; rows v with fixed[v] hold the Dirichlet data and are
/// kept exactly, the other rows are overwritten by the P1 solution of
/// Δu = 0 for each of the m columns. `mesh` holds triangles (dim 2) or
/// tetrahedra (dim 3), positively oriented. Throws warpfem::Error if PETSc
/// fails.
template <int dim>
void p1_harmonic_extension(const Mesh<dim>& mesh, const std::vector<bool>& fixed, MatrixX& values);

}  // namespace warpfem::mapping
