#pragma once
// `warpfem run`: one recipe for every physics (apps/run.cpp), read top to
// bottom in seven steps — config, map, mesh of Ω0, problem, solve, report,
// output. Kept in a library so tests drive exactly what users run.

#include <mpi.h>

#include <optional>
#include <string>
#include <vector>

#include "core/petsc/linear_solve.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "fem/physics/elasticity/transient_solver.hpp"
#include "io/config.hpp"

namespace warpfem::apps {

struct RunOptions {
  bool write_output = true;
  bool gather_solution = false;  ///< fill RunResult::solution
  bool compute_energy = false;   ///< transient: fill the energies of RunResult::history
};

/// What a run reports; the fields of the other physics keep their defaults.
struct RunResult {
  Index num_cells = 0;
  Index num_dofs = 0;  ///< scalar unknowns (components per node × nodes)
  double h = 0;        ///< largest edge length of the simple mesh
  double solve_seconds = 0;
  VectorX solution;  ///< every unknown in mesh order, components interleaved (if gathered)

  // Poisson: one linear solve.
  petsc::LinearSolveReport solve;
  std::optional<double> l2_error, h1_error;  ///< against the config's exact solution
  double area = 0;                           ///< of the warped domain
  int partial_levels = 0;  ///< multigrid levels this rank stored only around its cells (MPI)

  // Elasticity: Newton on each load or time step.
  std::vector<fem::LoadStep> load_steps;    ///< quasi-static: converged load steps
  int rejected_steps = 0;                   ///< quasi-static: halved increments
  int time_steps = 0;                       ///< transient
  int newton_iterations = 0;                ///< total
  int domain_rejections = 0;                ///< trial states rejected for det F <= 0
  std::vector<fem::TransientStep> history;  ///< transient: every step (energies if requested)
  double max_displacement = 0;              ///< max nodal |u| at the end
  double min_det_F = 0;                     ///< at the end

  // Output ("" and empty if disabled).
  std::string output_file;              ///< what ParaView opens: VTU/PVTU, or the PVD of a time series
  std::vector<std::string> vtk_files;   ///< every VTU/PVTU written
  Index output_subdivided_cells = 0;    ///< this rank's mesh cells written subdivided
  Index output_straightened_cells = 0;  ///< written cells drawn less curved to keep them untangled
  Index output_folded_cells = 0;        ///< written cells still folded
};

/// Runs a validated config on `comm`. Throws warpfem::Error if the map, mesh or a
/// solve fails (an elasticity solve first writes its last converged state).
RunResult run(const io::Config& config, MPI_Comm comm, const RunOptions& options = {});

}  // namespace warpfem::apps
