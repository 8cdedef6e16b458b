#include "core/environment.hpp"

#include <petscsys.h>

#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "core/petsc/check.hpp"

namespace warpfem {

Environment::Environment(int& argc, char**& argv) {
  WARPFEM_PETSC_CHECK(PetscInitialize(&argc, &argv, nullptr, nullptr));
  // Let exceptions, not PETSc's default handler, report problems; PETSc still
  // returns the error code through WARPFEM_PETSC_CHECK.
  WARPFEM_PETSC_CHECK(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
}

Environment::~Environment() {
  PetscPopErrorHandler();
  PetscFinalize();
}

int Environment::rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

int Environment::size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

void Environment::insert_petsc_options(const std::string& options, const std::string& origin) {
  if (options.empty()) return;
  // Command-line options take precedence: insert only names not yet set.
  std::istringstream in(options);
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const std::string& name = tokens[i];
    if (name.size() < 2 || name[0] != '-')
      throw Error("PETSc option string must start each option with '-', found \"" + name + "\"",
                  {.file = origin, .key_path = "", .hint = "write e.g. \"-ksp_type cg -pc_type gamg\""});
    std::string value;
    if (i + 1 < tokens.size() &&
        !(tokens[i + 1].size() > 1 && tokens[i + 1][0] == '-' &&
          !std::isdigit(static_cast<unsigned char>(tokens[i + 1][1])) && tokens[i + 1][1] != '.'))
      value = tokens[++i];
    PetscBool set = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set));
    if (!set)
      WARPFEM_PETSC_CHECK(
          PetscOptionsSetValue(nullptr, name.c_str(), value.empty() ? nullptr : value.c_str()));
  }
}

}  // namespace warpfem
