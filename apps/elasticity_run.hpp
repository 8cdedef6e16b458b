#pragma once
// The `warpfem run` pipeline for an elasticity config: map, mesh of Ω0,
// hyperelastic operator on the warped mesh, quasi-static load stepping (SNES)
// or transient generalized-α (TS), VTK output of every k-th step plus a PVD
// time series. Kept in a library so tests drive exactly what users run.

#include <mpi.h>

#include <string>
#include <vector>

#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "fem/physics/elasticity/transient_solver.hpp"
#include "io/elasticity_config.hpp"

namespace warpfem::apps {

struct ElasticityRunResult {
  Index num_cells = 0;
  Index num_dofs = 0;                       ///< scalar unknowns (2 per node)
  double h = 0;                             ///< largest edge length of the simple mesh
  std::vector<fem::LoadStep> load_steps;    ///< quasi-static: converged load steps
  int rejected_steps = 0;                   ///< quasi-static: halved increments
  int time_steps = 0;                       ///< transient
  int newton_iterations = 0;                ///< total
  int domain_rejections = 0;                ///< trial states rejected for det F <= 0
  std::vector<fem::TransientStep> history;  ///< transient: every step (energies if requested)
  double max_displacement = 0;              ///< max nodal |u| at the end
  double min_det_F = 0;                     ///< at the end
  double solve_seconds = 0;
  std::string pvd_file;  ///< "" if output disabled
  std::vector<std::string> vtk_files;
  VectorX displacement;  ///< every node x 2, interleaved (only if requested)
};

struct ElasticityRunOptions {
  bool write_output = true;
  bool gather_solution = false;
  bool compute_energy = false;  ///< transient: fill the energies of `history`
};

/// Runs the config. Throws warpfem::Error if the map, mesh or a solve fails; a failing solve
/// first writes the last converged state (when output is enabled).
ElasticityRunResult run_elasticity(const io::ElasticityConfig& config, MPI_Comm comm,
                                   const ElasticityRunOptions& options = {});

/// `warpfem run <config>` for a config with "problem": {"type": "elasticity"}: loads it, applies
/// --output-dir (if not empty), verbosity and PETSc options, runs on PETSC_COMM_WORLD. Returns 0.
int run_elasticity_command(const std::string& config_path, const std::string& output_dir);

}  // namespace warpfem::apps
