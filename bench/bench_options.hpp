#pragma once
// Command-line options of the benchmarks, read from PETSc's options database
// (so `-n 3 -type tetrahedron` sit beside PETSc's own options).

#include <petscsys.h>

#include <string>

#include "core/petsc/check.hpp"

namespace warpfem::bench {

inline PetscInt int_option(const char* name, PetscInt fallback) {
  PetscInt v = fallback;
  WARPFEM_PETSC_CHECK(PetscOptionsGetInt(nullptr, nullptr, name, &v, nullptr));
  return v;
}

inline std::string string_option(const char* name, const char* fallback) {
  char buf[PETSC_MAX_PATH_LEN] = {0};
  PetscBool set = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscOptionsGetString(nullptr, nullptr, name, buf, sizeof buf, &set));
  return set ? buf : fallback;
}

}  // namespace warpfem::bench
