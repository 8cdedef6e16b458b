#pragma once
// Transient elastodynamics M ü + c M u̇ + f_int(u) = f_ext(t) with PETSc's
// second-order generalized-α scheme (TSALPHA2, Chung & Hulbert 1993) through
// TSSetI2Function / TSSetI2Jacobian. ρ∞ = 1 gives the non-dissipative
// trapezoidal member (energy-conserving for linear problems); ρ∞ < 1 damps
// high frequencies. Every step is a Newton solve (fem/elasticity/newton.hpp);
// TS options go under the same prefix (-elasticity_ts_monitor, ...).

#include <functional>

#include "fem/physics/elasticity/newton.hpp"

namespace warpfem::fem {

struct TransientOptions {
  double time_step = 1e-2;
  double end_time = 1.0;
  double rho_infinity = 1.0;    ///< spectral radius at infinite frequency, in [0, 1]
  double damping = 0.0;         ///< mass-proportional damping coefficient c [1/s]
  int max_step_failures = 8;    ///< Newton failures allowed (each retries with a smaller step)
  bool compute_energy = false;  ///< fill the energies of TransientStep (extra assembly passes)
};

struct TransientStep {
  int step = 0;
  double time = 0;
  int newton_iterations = 0;                                        ///< of this step
  double kinetic_energy = 0, strain_energy = 0, external_work = 0;  ///< if compute_energy
  double total_energy() const { return kinetic_energy + strain_energy - external_work; }
};

struct TransientReport {
  int steps = 0;
  int newton_iterations = 0;
  double final_time = 0;
  int domain_rejections = 0;
};

template <int dim>
class TransientSolver {
 public:
  TransientSolver(const HyperelasticOperator<dim>& op, TransientOptions options, NewtonOptions newton = {});

  /// Integrates from t = 0 with displacement `u` and velocity `v` (both updated in place).
  /// `on_step` runs at t = 0 (step 0) and after every step. Throws warpfem::Error if a step
  /// cannot be solved; u, v then hold the last completed step.
  TransientReport solve(Vec u, Vec v,
                        const std::function<void(const TransientStep&, Vec u, Vec v)>& on_step = {});

 private:
  static PetscErrorCode form_residual(TS ts, PetscReal t, Vec U, Vec V, Vec A, Vec F, void* ctx);
  static PetscErrorCode form_jacobian(TS ts, PetscReal t, Vec U, Vec V, Vec A, PetscReal shiftV,
                                      PetscReal shiftA, Mat J, Mat P, void* ctx);
  static PetscErrorCode monitor(TS ts, PetscInt step, PetscReal t, Vec U, void* ctx);
  TransientStep make_step(int step, double t, Vec u, Vec v) const;

  const HyperelasticOperator<dim>& op_;
  TransientOptions options_;
  NewtonOptions newton_;
  NewtonContext context_;
  petsc::Vector r_, inertia_;
  petsc::Matrix J_;
  petsc::TimeStepper ts_;
  const std::function<void(const TransientStep&, Vec, Vec)>* on_step_ = nullptr;
  TransientReport report_;
  PetscInt last_snes_iterations_ = 0;
};

}  // namespace warpfem::fem
