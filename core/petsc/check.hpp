#pragma once
// The single place where PETSc error codes become C++ exceptions.

#include <petscsys.h>

#include <string>

#include "core/error.hpp"

namespace warpfem::petsc {

/// Throws warpfem::Error describing the PETSc error `code` raised by `call`.
[[noreturn]] void throw_error(PetscErrorCode code, const char* call, const char* file, int line);

}  // namespace warpfem::petsc

/// Evaluates a PETSc call and throws warpfem::Error if it does not return 0.
#define WARPFEM_PETSC_CHECK(call)                                                    \
  do {                                                                               \
    const PetscErrorCode warpfem_petsc_ierr_ = (call);                               \
    if (warpfem_petsc_ierr_ != 0)                                                    \
      ::warpfem::petsc::throw_error(warpfem_petsc_ierr_, #call, __FILE__, __LINE__); \
  } while (0)
