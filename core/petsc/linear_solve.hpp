#pragma once
// One linear solve with PETSc's KSP: defaults set in code, then overridden by
// the options database (config "petsc_options" and the command line).

#include <petscksp.h>

#include <string>

namespace warpfem::petsc {

struct LinearSolveOptions {
  std::string ksp_type = "cg";
  std::string pc_type = "gamg";
  double rtol = 1e-10;
  double atol = 1e-50;
  int max_iterations = 10000;
  std::string prefix;  ///< PETSc options prefix, e.g. "poisson_"
  /// Systems with fewer unknowns are solved by LU (algebraic multigrid has nothing
  /// to coarsen there and can fail on a handful of interior unknowns). 0 disables.
  int direct_below = 500;
};

struct LinearSolveReport {
  int iterations = 0;
  double residual_norm = 0;
  std::string ksp_type, pc_type;
  std::string converged_reason;
  bool converged = false;
  double setup_seconds = 0, solve_seconds = 0;
};

/// Fills iterations, residual norm, KSP/PC types and the converged reason of a finished solve.
void collect_solve_outcome(KSP ksp, LinearSolveReport& report);

/// Throws warpfem::Error "<solver> diverged after N iterations: <reason> (residual norm r)"
/// with key path /solver and `hint` unless the solve converged.
void throw_if_diverged(const LinearSolveReport& report, const std::string& solver, const std::string& hint);

/// Solves A x = b (x is the initial guess on entry). Throws warpfem::Error with
/// PETSc's reason and a hint if the solver diverges.
LinearSolveReport solve_linear_system(Mat A, Vec b, Vec x, const LinearSolveOptions& options);

}  // namespace warpfem::petsc

namespace warpfem::petsc {

/// Estimate of the spectral condition number σmax/σmin of the (SPD) matrix A
/// from the Lanczos information of an unpreconditioned CG solve (PETSc's
/// KSPComputeExtremeSingularValues) with a random right-hand side.
double estimate_condition_number(Mat A, int max_iterations = 20000);

}  // namespace warpfem::petsc
