#pragma once
// The `warpfem run` pipeline for a Poisson config: map, mesh, assemble, solve,
// report, write. Kept in a library so tests drive exactly what users run.

#include <mpi.h>

#include <optional>
#include <string>

#include "core/petsc/linear_solve.hpp"
#include "io/run_config.hpp"

namespace warpfem::apps {

struct PoissonRunResult {
  Index num_cells = 0;
  Index num_dofs = 0;
  double h = 0;  ///< largest edge length of the simple mesh
  petsc::LinearSolveReport solve;
  std::optional<double> l2_error, h1_error;
  double area = 0;
  std::string output_file;  ///< VTU/PVTU path ("" if output disabled)
  /// This rank's mesh cells written subdivided, and written cells still folded.
  Index output_subdivided_cells = 0, output_folded_cells = 0;
  VectorX solution;  ///< every DOF in mesh order (only if requested)
};

struct PoissonRunOptions {
  bool write_output = true;
  bool gather_solution = false;
};

PoissonRunResult run_poisson(const io::RunConfig& config, MPI_Comm comm,
                             const PoissonRunOptions& options = {});

}  // namespace warpfem::apps
