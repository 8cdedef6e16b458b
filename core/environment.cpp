#include "core/environment.hpp"

#include <petscsys.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/sanitizer.hpp"

namespace warpfem {

namespace {

bool started_by_launcher(const std::function<const char*(const char*)>& env) {
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (env(launched)) return true;
  return false;
}

}  // namespace

std::string Environment::singleton_session_base(const std::function<const char*(const char*)>& env,
                                                long pid) {
  if (started_by_launcher(env) || env("OMPI_MCA_orte_tmpdir_base")) return {};
  const char* tmp = env("TMPDIR");
  return std::string(tmp && *tmp ? tmp : "/tmp") + "/warpfem-mpi-" + std::to_string(pid);
}

std::vector<std::pair<std::string, std::string>> Environment::mca_defaults(
    const std::function<const char*(const char*)>& env) {
  if (!started_by_launcher(env)) return {{"OMPI_MCA_ess_singleton_isolated", "1"}, {"OMPI_MCA_pml", "ob1"}};
  const char* size = env("OMPI_COMM_WORLD_SIZE");
  const char* local_size = env("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (size && local_size && *size && std::string_view(size) == local_size) return {{"OMPI_MCA_pml", "ob1"}};
  return {};
}

Environment::Environment(int& argc, char**& argv) {
  int mpi_initialized = 0;
  MPI_Initialized(&mpi_initialized);
  if (!mpi_initialized) {
    session_base_ = singleton_session_base([](const char* name) { return std::getenv(name); },
                                           static_cast<long>(getpid()));
    if (!session_base_.empty() && setenv("OMPI_MCA_orte_tmpdir_base", session_base_.c_str(), 0) != 0)
      session_base_.clear();
    for (const auto& [name, value] : mca_defaults([](const char* name) { return std::getenv(name); }))
      setenv(name.c_str(), value.c_str(), 0);  // a failure keeps Open MPI's defaults: slower, not wrong
  }
#if WARPFEM_ADDRESS_SANITIZER
  // PETSc's signal handler would replace AddressSanitizer's: it runs on the
  // faulting stack (a stack overflow then dies silently) and prints no stack trace.
  WARPFEM_PETSC_CHECK(PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr));
#endif
  WARPFEM_PETSC_CHECK(PetscInitialize(&argc, &argv, nullptr, nullptr));
  // Let exceptions, not PETSc's default handler, report problems; PETSc still
  // returns the error code through WARPFEM_PETSC_CHECK.
  WARPFEM_PETSC_CHECK(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
}

Environment::~Environment() {
  PetscPopErrorHandler();
  PetscFinalize();
  if (!session_base_.empty()) {
    std::error_code ignored;  // best effort: Open MPI has removed its own directories by now
    std::filesystem::remove_all(session_base_, ignored);
  }
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
