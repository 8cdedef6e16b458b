#pragma once
// An upper bound on the spectrum of the Jacobi-preconditioned operator D⁻¹A
// without a Krylov estimate: Gershgorin's row sums,
//
//   λmax(D⁻¹A) ≤ max_i Σ_j |a_ij| / a_ii .
//
// For first-order Lagrange stiffness matrices (P1, Q1) the off-diagonal
// entries are mostly negative and the bound is close to λmax on fine meshes
// (2.37 against PETSc's estimate 2.29 on the L-shape at 1.24 M DOFs, 2.65
// against 2.47 on the warped gear; up to ~25 % above λmax on meshes of a few
// hundred DOFs), so Chebyshev–Jacobi smooths as well with it as with PETSc's
// 10-step CG estimate, which costs ~10 matrix-vector products per level
// (BENCHMARKS.md has what that is worth at set-up). Second-order matrices have positive
// couplings and the bound overshoots by 30–130 %, which costs iterations there.

#include <petscmat.h>

namespace warpfem::multigrid {

/// max over rows of Σ_j |a_ij| / a_ii, over all ranks of A's communicator
/// (collective). A must be MATSEQAIJ or MATMPIAIJ (or a type that supports
/// MatGetRow) with a positive diagonal; throws warpfem::Error naming the
/// first row whose diagonal is not positive.
double jacobi_gershgorin_bound(Mat A);

/// The same bound from this rank's rows given as their diagonal entries and
/// Σ_j |a_ij| (`rows` of them, the first with global index `first_row`):
/// collective over `comm`; every rank throws warpfem::Error if any rank has a
/// diagonal entry that is not positive.
double jacobi_gershgorin_bound(MPI_Comm comm, const double* diagonal, const double* row_abs_sum,
                               PetscInt rows, PetscInt first_row);

}  // namespace warpfem::multigrid
