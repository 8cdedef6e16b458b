#include "core/petsc/check.hpp"

namespace warpfem::petsc {

void throw_error(PetscErrorCode code, const char* call, const char* file, int line) {
  const char* text = nullptr;
  char* specific = nullptr;  // the message of the error's origin, e.g. a warpfem callback's
  PetscErrorMessage(code, &text, &specific);
  std::string message = std::string("PETSc error ") + std::to_string(code) + " (" +
                        (text ? text : "unknown") + ") in " + call + " at " + file + ":" +
                        std::to_string(line);
  if (specific && *specific) message += ": " + std::string(specific);
  throw Error(message);
}

}  // namespace warpfem::petsc
