#pragma once
// RAII set-up of MPI and PETSc for one process. Works both under mpiexec and
// as a plain executable (MPI singleton). Create exactly one per process,
// before any other warpfem object that talks to MPI or PETSc.

#include <mpi.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace warpfem {

class Environment {
 public:
  /// Initializes MPI (if not yet) and PETSc. PETSc reads its options from
  /// argv, so `-ksp_type cg` on the command line reaches every solver.
  ///
  /// A process not started by mpiexec (an Open MPI singleton) gets its own
  /// Open MPI session directory, `$TMPDIR/warpfem-mpi-<pid>` (removed again at
  /// exit), unless OMPI_MCA_orte_tmpdir_base is set: singletons started at the
  /// same moment otherwise race on creating the shared one and one of them
  /// aborts ("A call to mkdir was unable to create the desired directory ...
  /// File exists", open-mpi/ompi#8510) — seen under `ctest -j`, and possible in
  /// any script that starts several runs at once.
  ///
  /// Open MPI parameters from mca_defaults() are set before MPI starts
  /// (variables already set keep their values).
  Environment(int& argc, char**& argv);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

  static int rank(MPI_Comm comm = MPI_COMM_WORLD);
  static int size(MPI_Comm comm = MPI_COMM_WORLD);

  /// Inserts a string of PETSc options ("-ksp_type cg -pc_type gamg") into the
  /// global options database. Options already given on the command line win.
  static void insert_petsc_options(const std::string& options, const std::string& origin);

  /// The base a process with environment `env` and id `pid` gets before MPI
  /// starts: "$TMPDIR/warpfem-mpi-<pid>" (TMPDIR empty: /tmp), or empty if a
  /// launcher started it (OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_RANK set) or
  /// OMPI_MCA_orte_tmpdir_base is already set.
  static std::string singleton_session_base(const std::function<const char*(const char*)>& env, long pid);

  /// Open MPI parameters for this process, as environment variables.
  ///  - No launcher started it (a singleton): no support daemon
  ///    (`ess_singleton_isolated`: warpfem never spawns processes) and the ob1
  ///    point-to-point layer, which a single process needs nothing else from.
  ///  - Open MPI's mpiexec started every rank on this one node
  ///    (OMPI_COMM_WORLD_LOCAL_SIZE = OMPI_COMM_WORLD_SIZE): ob1, whose
  ///    shared-memory transport is what ranks on one node talk through. Every
  ///    rank sees the same two sizes, so all choose alike.
  /// Without ob1, MPI_Init opens every network library, whose start-up waits
  /// for hardware that may not exist (Debian's PSM2 polls for Omni-Path
  /// adapters), which costs more than a small run. Empty otherwise (ranks on
  /// several nodes, or another launcher): they keep what mpiexec chose.
  static std::vector<std::pair<std::string, std::string>> mca_defaults(
      const std::function<const char*(const char*)>& env);

 private:
  std::string session_base_;  ///< this singleton's own session base, removed at exit; empty if none
};

}  // namespace warpfem
