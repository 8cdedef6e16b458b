#pragma once
// The Newton solver set-up shared by the quasi-static and the transient
// drivers: SNESNEWTONLS with warpfem's backtracking line search (a
// SNESLINESEARCHSHELL): the step is halved until the trial state is admissible
// (the residual reports det F ≤ 0 as a domain error) and either the residual
// norm decreases sufficiently or, where the driver provides one, the potential
// energy decreases (robust for large rotations, where the residual norm first
// grows). Plus a residual monitor and the linear solver defaults.
// Everything can be overridden with PETSc options under the prefix
// (default "elasticity_": -elasticity_snes_monitor, -elasticity_ksp_type gmres, ...).

#include <petscsnes.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/petsc/handles.hpp"
#include "fem/physics/elasticity/callback_guard.hpp"
#include "fem/physics/elasticity/hyperelastic_operator.hpp"

namespace warpfem::fem {

struct NewtonOptions {
  double rtol = 1e-9;       ///< stop when |R| <= rtol |R_0| ...
  double atol = 1e-10;      ///< ... or |R| <= atol
  int max_iterations = 25;  ///< Newton iterations per load or time step
  /// ... or when the full Newton correction is below step_tolerance |u|: the residual has reached
  /// its round-off floor, which rtol |R_0| (small after a good predictor) and atol may lie below.
  double step_tolerance = 1e-10;
  std::string ksp_type = "preonly";
  std::string pc_type = "lu";
  std::string factor_solver = "mumps";  ///< for pc_type lu/cholesky; "" keeps PETSc's default
  /// "warpfem": the backtracking line search above; any PETSc type ("bt", "basic", ...) for comparison.
  std::string line_search = "warpfem";
  int max_halvings = 20;       ///< of the warpfem line search
  bool log_iterations = true;  ///< log |R| of every Newton iteration (info level)
  std::string prefix = "elasticity_";
  /// Optional: sets up the preconditioner of the Newton steps' KSP once its type is
  /// set, given the Jacobian matrix (e.g. the geometric multigrid of multigrid/,
  /// which fem/ cannot depend on). Runs before the options database is applied.
  std::function<void(KSP ksp, Mat jacobian)> configure_preconditioner;
};

/// State shared with the PETSc callbacks of one SNES.
struct NewtonContext {
  CallbackGuard guard;
  petsc::Vector work;
  std::vector<double> residuals;       ///< |R| per iteration of the current solve
  std::vector<int> linear_iterations;  ///< Krylov iterations of each Newton step of the current solve
  PetscInt linear_total = 0;           ///< SNES's running count when the last step was recorded
  int domain_rejections = 0;           ///< residual evaluations rejected for det F <= 0
  int step_halvings = 0;               ///< line-search halvings of Newton steps
  bool log_iterations = true;
  int max_halvings = 20;
  double step_tolerance = 0;
  /// Potential energy whose gradient is the residual (nullopt: inadmissible); may be empty.
  std::function<std::optional<double>(Vec)> objective;
  bool in_line_search = false;
  bool trial_rejected = false;

  /// Called by a residual callback that found det F <= 0: inside the line search the trial is
  /// rejected (and the step shortened); elsewhere the SNES gets a function domain error.
  void reject(SNES snes);
};

/// Configures `snes` (type, tolerances, line search, pre-check, monitor, KSP/PC) and
/// applies the options database under options.prefix. `context` must outlive the SNES.
void configure_newton(SNES snes, const NewtonOptions& options, NewtonContext& context,
                      Mat jacobian = nullptr);

/// Text of a SNES converged reason ("CONVERGED_FNORM_RELATIVE", "DIVERGED_LINE_SEARCH", ...).
std::string reason_text(SNESConvergedReason reason);

}  // namespace warpfem::fem
