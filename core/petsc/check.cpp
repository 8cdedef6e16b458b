#include "core/petsc/check.hpp"

namespace warpfem::petsc {

void throw_error(PetscErrorCode code, const char* call, const char* file, int line) {
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw Error(std::string("PETSc error ") + std::to_string(code) + " (" + (text ? text : "unknown") +
              ") in " + call + " at " + file + ":" + std::to_string(line));
}

}  // namespace warpfem::petsc
