// Probe for apps::FatalErrorHandler, run under mpiexec by CTest:
//   fatal_error_probe local  — rank 1 fails alone while rank 0 waits for it in a collective
//                              call (the case that used to hang);
//   fatal_error_probe all    — every rank fails with the same error (e.g. a config error).
// Either way every rank must end, with a non-zero exit code and the message printed once.

#include <mpi.h>

#include <string>

#include "apps/fatal_error.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  warpfem::Environment env(argc, argv);
  warpfem::apps::FatalErrorHandler fatal(2.0);
  try {
    if (mode == "all" || (mode == "local" && warpfem::Environment::rank() == 1))
      throw warpfem::Error("simulated failure", {.file = "probe.json", .key_path = "/mode", .hint = mode});
    MPI_Barrier(MPI_COMM_WORLD);  // with "local", rank 0 waits here for rank 1 forever
  } catch (const warpfem::Error& e) {
    return fatal.fail(e.what());
  }
  return 0;
}
