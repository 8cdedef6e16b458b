#pragma once
// Moving distributed vector entries to where they are read.

#include <petscvec.h>

#include <vector>

#include "core/types.hpp"

namespace warpfem::petsc {

/// Runs a forward scatter from `from` into the sequential vector `to` and returns to's values.
VectorX scatter_forward(VecScatter scatter, Vec from, Vec to);

/// Every entry of the parallel vector `v`, in PETSc's global order, on every rank (collective).
std::vector<PetscScalar> gather_to_all(Vec v);

}  // namespace warpfem::petsc
