#pragma once
// Quasi-static hyperelasticity with adaptive load stepping: the load factor s
// runs from 0 to 1 (all loads and prescribed displacements are scaled by s),
// each increment is solved by Newton (fem/elasticity/newton.hpp) whose line
// search also accepts decrease of the potential energy Π(u) = ∫W(F) − s f_ext·u,
// starting from a linearized predictor of the prescribed displacement increment. A failed
// increment is retried with half the increment, down to a minimum, and then
// fails with a warpfem::Error; the displacement keeps the last converged state.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fem/physics/elasticity/newton.hpp"
#include "fem/physics/elasticity/tangent_inertia.hpp"

namespace warpfem::fem {

struct LoadSteppingOptions {
  int steps = 1;                ///< initial number of equal increments of s
  double min_increment = 1e-4;  ///< give up when a failed increment would drop below this
};

struct LoadStep {
  double load = 0;                     ///< s after the step
  double increment = 0;                ///< Δs of the step
  int iterations = 0;                  ///< Newton iterations
  std::vector<double> residuals;       ///< |R| per Newton iteration (iteration 0 first)
  std::vector<int> linear_iterations;  ///< Krylov iterations of each Newton step (1 each with LU)
  double seconds = 0;
};

struct QuasiStaticReport {
  std::vector<LoadStep> steps;  ///< converged steps
  int rejected_steps = 0;       ///< increments that failed and were halved
  int domain_rejections = 0;    ///< residuals rejected for det F <= 0
  int step_halvings = 0;        ///< line-search halvings of Newton steps
  /// Negative eigenvalues of the tangent at the final state (with a direct linear solver; -1: not
  /// checked). Newton converges onto unstable equilibria too, e.g. after a load step that passes
  /// a point where the path loses stability; such a state is warned about.
  PetscInt final_negative_eigenvalues = -1;
  int newton_iterations() const;
};

template <int dim>
class QuasiStaticSolver {
 public:
  QuasiStaticSolver(const HyperelasticOperator<dim>& op, NewtonOptions newton = {},
                    LoadSteppingOptions steps = {});

  /// Solves for s = 0 → 1 starting from `u` (the state at s = 0, normally zero) and leaves the
  /// result in `u`. `on_step` runs after every converged step (for output). Throws warpfem::Error
  /// when the load cannot be applied; `u` then holds the last converged state.
  QuasiStaticReport solve(Vec u, const std::function<void(const LoadStep&, Vec)>& on_step = {});

 private:
  static PetscErrorCode form_residual(SNES snes, Vec u, Vec r, void* ctx);
  static PetscErrorCode form_jacobian(SNES snes, Vec u, Mat J, Mat P, void* ctx);
  /// Initial guess of a load step: the prescribed-displacement increment plus its linearized
  /// response (one Newton step about the converged state), if that is admissible.
  void predict(Vec u, double load, Vec trial);
  /// After the first failed increment from the converged state `u` at `load`: is that equilibrium
  /// stable (tangent positive definite)? An unstable one is warned about; either way the
  /// answer is kept for the error message should the load step never succeed.
  void check_stability(Vec u, double load, double increment, int reason);
  std::optional<TangentStability> stability_at(Vec u);
  /// After a failed increment from the converged state `u`: does its last Newton iterate `x` show
  /// the loss of stability that no smaller increment gets past, i.e. a tangent with negative
  /// eigenvalues while a cell of x or u folds between its quadrature points (det F <= 0 inside
  /// the cell)? Returns its description, or "".
  std::string instability_of_iterate(Vec x, Vec u);

  const HyperelasticOperator<dim>& op_;
  NewtonOptions newton_;
  LoadSteppingOptions stepping_;
  NewtonContext context_;
  double load_ = 0;
  std::optional<TangentStability> reference_;  ///< of the tangent at u = 0
  std::string stability_summary_;              ///< of the last stability check
  petsc::Vector r_, delta_, rhs_;
  petsc::Matrix J_;
  petsc::NonlinearSolver snes_;
};

}  // namespace warpfem::fem
