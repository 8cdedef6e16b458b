#include "fem/physics/elasticity/transient_solver.hpp"

#include <sstream>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::fem {

template <int dim>
TransientSolver<dim>::TransientSolver(const HyperelasticOperator<dim>& op, TransientOptions options,
                                      NewtonOptions newton)
    : op_(op), options_(options), newton_(std::move(newton)) {
  require(options_.time_step > 0, "the time step must be positive");
  require(options_.end_time > 0, "the end time must be positive");
  require(options_.rho_infinity >= 0 && options_.rho_infinity <= 1, "rho_infinity must lie in [0, 1]");
  r_ = op_.space().create_vector();
  inertia_ = op_.space().create_vector();
  J_ = op_.space().create_matrix(newton_.prefix.c_str());
  op_.set_near_null_space(J_.get());
  WARPFEM_PETSC_CHECK(TSCreate(op_.space().comm(), ts_.out()));
  WARPFEM_PETSC_CHECK(TSSetOptionsPrefix(ts_.get(), newton_.prefix.c_str()));
  WARPFEM_PETSC_CHECK(TSSetType(ts_.get(), TSALPHA2));
  WARPFEM_PETSC_CHECK(TSAlpha2SetRadius(ts_.get(), options_.rho_infinity));
  WARPFEM_PETSC_CHECK(TSSetI2Function(ts_.get(), r_.get(), form_residual, this));
  WARPFEM_PETSC_CHECK(TSSetI2Jacobian(ts_.get(), J_.get(), J_.get(), form_jacobian, this));
  WARPFEM_PETSC_CHECK(TSSetTimeStep(ts_.get(), options_.time_step));
  WARPFEM_PETSC_CHECK(TSSetMaxTime(ts_.get(), options_.end_time));
  WARPFEM_PETSC_CHECK(TSSetMaxSteps(ts_.get(), 100000000));
  WARPFEM_PETSC_CHECK(TSSetExactFinalTime(ts_.get(), TS_EXACTFINALTIME_MATCHSTEP));
  WARPFEM_PETSC_CHECK(TSSetMaxSNESFailures(ts_.get(), options_.max_step_failures));
  WARPFEM_PETSC_CHECK(TSMonitorSet(ts_.get(), monitor, this, nullptr));
  SNES snes = nullptr;
  WARPFEM_PETSC_CHECK(TSGetSNES(ts_.get(), &snes));
  NewtonOptions quiet = newton_;
  quiet.log_iterations = false;  // one line per time step instead; -elasticity_snes_monitor shows them
  configure_newton(snes, quiet, context_, J_.get());
  WARPFEM_PETSC_CHECK(TSSetFromOptions(ts_.get()));
}

template <int dim>
PetscErrorCode TransientSolver<dim>::form_residual(TS ts, PetscReal t, Vec U, Vec V, Vec A, Vec F,
                                                   void* ctx) {
  auto* self = static_cast<TransientSolver*>(ctx);
  return self->context_.guard.run([&] {
    // inertia = A + c V, multiplied by the mass matrix inside the operator
    WARPFEM_PETSC_CHECK(VecWAXPY(self->inertia_.get(), self->options_.damping, V, A));
    if (!self->op_.residual(U, self->inertia_.get(), 1.0, t, F)) {
      SNES snes = nullptr;
      WARPFEM_PETSC_CHECK(TSGetSNES(ts, &snes));
      self->context_.reject(snes);
    }
  });
}

template <int dim>
PetscErrorCode TransientSolver<dim>::form_jacobian(TS, PetscReal, Vec U, Vec, Vec, PetscReal shiftV,
                                                   PetscReal shiftA, Mat J, Mat P, void* ctx) {
  auto* self = static_cast<TransientSolver*>(ctx);
  return self->context_.guard.run([&] {
    self->op_.jacobian(U, shiftA + self->options_.damping * shiftV, P);
    if (J != P) {
      WARPFEM_PETSC_CHECK(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
      WARPFEM_PETSC_CHECK(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
    }
  });
}

template <int dim>
TransientStep TransientSolver<dim>::make_step(int step, double t, Vec u, Vec v) const {
  TransientStep s;
  s.step = step;
  s.time = t;
  if (options_.compute_energy) {
    s.kinetic_energy = op_.kinetic_energy(v);
    s.strain_energy = op_.strain_energy(u);
    s.external_work = op_.external_work(u, 1.0, t);
  }
  return s;
}

template <int dim>
PetscErrorCode TransientSolver<dim>::monitor(TS ts, PetscInt step, PetscReal t, Vec U, void* ctx) {
  auto* self = static_cast<TransientSolver*>(ctx);
  return self->context_.guard.run([&] {
    Vec u = nullptr, v = nullptr;
    WARPFEM_PETSC_CHECK(TS2GetSolution(ts, &u, &v));
    (void)U;
    TransientStep s = self->make_step(static_cast<int>(step), t, u, v);
    PetscInt its = 0;
    WARPFEM_PETSC_CHECK(TSGetSNESIterations(ts, &its));
    s.newton_iterations = static_cast<int>(its - self->last_snes_iterations_);
    self->last_snes_iterations_ = its;
    self->report_.steps = static_cast<int>(step);
    self->report_.final_time = t;
    self->report_.newton_iterations = static_cast<int>(its);
    if (step > 0) log::info("  step ", step, ": t = ", t, ", ", s.newton_iterations, " Newton iterations");
    if (*self->on_step_) (*self->on_step_)(s, u, v);
  });
}

template <int dim>
TransientReport TransientSolver<dim>::solve(
    Vec u, Vec v, const std::function<void(const TransientStep&, Vec, Vec)>& on_step) {
  on_step_ = &on_step;
  report_ = {};
  last_snes_iterations_ = 0;
  op_.apply_dirichlet(u, 1.0, 0.0);
  op_.zero_constrained(v);
  WARPFEM_PETSC_CHECK(TS2SetSolution(ts_.get(), u, v));
  const PetscErrorCode ierr = TSSolve(ts_.get(), u);
  on_step_ = nullptr;
  context_.guard.rethrow_if_failed();
  WARPFEM_PETSC_CHECK(ierr);
  TSConvergedReason reason;
  WARPFEM_PETSC_CHECK(TSGetConvergedReason(ts_.get(), &reason));
  report_.domain_rejections = context_.domain_rejections;
  if (reason < 0) {
    std::ostringstream os;
    os << "transient solve failed at t = " << report_.final_time << " after " << report_.steps << " steps ("
       << TSConvergedReasons[reason] << ")";
    throw Error(os.str(), {.file = "", .key_path = "", .hint = "reduce the time step or the loads"});
  }
  return report_;
}

template class TransientSolver<2>;
template class TransientSolver<3>;

}  // namespace warpfem::fem
