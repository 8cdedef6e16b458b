#pragma once
// The two solves of hyperelasticity in the run recipe: quasi-static load
// stepping (load factor 0 → 1, SNES on each step) and transient generalized-α
// time stepping (TS). Both write every k-th converged state (and the last) to
// the run's output and, when a step fails, the last converged one before the
// error — placed at the config key the user can change.

#include <petscvec.h>

#include "apps/run.hpp"
#include "fem/physics/elasticity/hyperelastic_operator.hpp"
#include "fem/physics/elasticity/newton.hpp"

namespace warpfem::apps {

template <int dim>
class RunOutput;

template <int dim>
struct SteppingContext {
  const io::ElasticityRunConfig<dim>& config;
  const fem::HyperelasticOperator<dim>& op;
  const fem::NewtonOptions& newton;
  RunOutput<dim>* output = nullptr;  ///< null: nothing written
  bool compute_energy = false;
};

/// Solves from `u` (the initial state, the result in place).
template <int dim>
void solve_quasi_static(const SteppingContext<dim>& context, Vec u, RunResult& result);
template <int dim>
void solve_transient(const SteppingContext<dim>& context, Vec u, RunResult& result);

}  // namespace warpfem::apps
