#pragma once
// Stability of an equilibrium from its symmetric tangent stiffness J: the
// inertia (numbers of negative, zero and positive eigenvalues) from a sparse
// LDLᵀ factorization (MUMPS), and J's eigenvalue nearest zero on a subspace by
// inverse iteration with the same factors (the lowest one when J is positive
// definite). A stable equilibrium has a positive definite tangent; an eigenvalue
// falling towards zero along the load
// path announces a limit or bifurcation point (buckling, a crease), which no
// smaller load increment can step past.

#include <petscmat.h>

#include <optional>

namespace warpfem::fem {

struct TangentStability {
  PetscInt negative = 0, zero = 0, positive = 0;  ///< inertia of J
  double eigenvalue_nearest_zero = 0;             ///< of J on the subspace of the start vector
};

/// Inertia of the symmetric matrix `J` and its eigenvalue of smallest magnitude on the
/// invariant subspace containing `start` (e.g. the free DOFs of a J with identity rows and
/// columns on constrained DOFs: give a start vector that is zero there). Collective.
/// std::nullopt when PETSc has no MUMPS or the factorization fails (singular J).
std::optional<TangentStability> tangent_stability(Mat J, Vec start, int iterations = 30);

}  // namespace warpfem::fem
