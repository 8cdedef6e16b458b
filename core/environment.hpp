#pragma once
// RAII set-up of MPI and PETSc for one process. Works both under mpiexec and
// as a plain executable (MPI singleton). Create exactly one per process,
// before any other warpfem object that talks to MPI or PETSc.

#include <mpi.h>

#include <string>

namespace warpfem {

class Environment {
 public:
  /// Initializes MPI (if not yet) and PETSc. PETSc reads its options from
  /// argv, so `-ksp_type cg` on the command line reaches every solver.
  Environment(int& argc, char**& argv);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

  static int rank(MPI_Comm comm = MPI_COMM_WORLD);
  static int size(MPI_Comm comm = MPI_COMM_WORLD);

  /// Inserts a string of PETSc options ("-ksp_type cg -pc_type gamg") into the
  /// global options database. Options already given on the command line win.
  static void insert_petsc_options(const std::string& options, const std::string& origin);
};

}  // namespace warpfem
