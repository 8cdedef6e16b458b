#include "fem/physics/elasticity/quasi_static_solver.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"

namespace warpfem::fem {

int QuasiStaticReport::newton_iterations() const {
  return std::accumulate(steps.begin(), steps.end(), 0,
                         [](int n, const LoadStep& s) { return n + s.iterations; });
}

template <int dim>
QuasiStaticSolver<dim>::QuasiStaticSolver(const HyperelasticOperator<dim>& op, NewtonOptions newton,
                                          LoadSteppingOptions steps)
    : op_(op), newton_(std::move(newton)), stepping_(steps) {
  require(stepping_.steps >= 1, "load stepping needs at least one step");
  require(stepping_.min_increment > 0, "the minimum load increment must be positive");
  r_ = op_.space().create_vector();
  J_ = op_.space().create_matrix(newton_.prefix.c_str());
  op_.set_near_null_space(J_.get());
  WARPFEM_PETSC_CHECK(SNESCreate(op_.space().comm(), snes_.out()));
  WARPFEM_PETSC_CHECK(SNESSetFunction(snes_.get(), r_.get(), form_residual, this));
  WARPFEM_PETSC_CHECK(SNESSetJacobian(snes_.get(), J_.get(), J_.get(), form_jacobian, this));
  context_.objective = [this](Vec u) { return op_.potential_energy(u, load_, 1.0); };
  configure_newton(snes_.get(), newton_, context_, J_.get());
  delta_ = op_.space().create_vector();
  rhs_ = op_.space().create_vector();
}

template <int dim>
void QuasiStaticSolver<dim>::predict(Vec u, double load, Vec trial) {
  WARPFEM_PETSC_CHECK(VecCopy(u, trial));
  op_.apply_dirichlet(trial, load, 1.0);
  WARPFEM_PETSC_CHECK(VecWAXPY(delta_.get(), -1.0, u, trial));  // nonzero on constrained DOFs only
  PetscReal norm = 0;
  WARPFEM_PETSC_CHECK(VecNorm(delta_.get(), NORM_INFINITY, &norm));
  if (norm == 0) return;
  // Solve K_II δ_I = −(R_I(u) + K_ID Δ_D) with K = K(u), i.e. one Newton step for the new boundary values.
  op_.jacobian(u, 0.0, J_.get(), false);
  WARPFEM_PETSC_CHECK(MatMult(J_.get(), delta_.get(), rhs_.get()));
  if (!op_.residual(u, nullptr, load, 1.0, r_.get())) return;
  WARPFEM_PETSC_CHECK(VecAXPY(rhs_.get(), 1.0, r_.get()));
  op_.zero_constrained(rhs_.get());
  WARPFEM_PETSC_CHECK(VecScale(rhs_.get(), -1.0));
  op_.jacobian(u, 0.0, J_.get(), true);
  KSP ksp = nullptr;
  WARPFEM_PETSC_CHECK(SNESGetKSP(snes_.get(), &ksp));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp, J_.get(), J_.get()));
  WARPFEM_PETSC_CHECK(KSPSolve(ksp, rhs_.get(), r_.get()));
  KSPConvergedReason reason;
  WARPFEM_PETSC_CHECK(KSPGetConvergedReason(ksp, &reason));
  if (reason < 0) return;
  WARPFEM_PETSC_CHECK(VecAXPY(r_.get(), 1.0, trial));  // u + Δ + δ
  if (op_.min_det_F(r_.get()) > 0) WARPFEM_PETSC_CHECK(VecCopy(r_.get(), trial));
}

template <int dim>
PetscErrorCode QuasiStaticSolver<dim>::form_residual(SNES snes, Vec u, Vec r, void* ctx) {
  auto* self = static_cast<QuasiStaticSolver*>(ctx);
  return self->context_.guard.run([&] {
    if (!self->op_.residual(u, nullptr, self->load_, 1.0, r)) self->context_.reject(snes);
  });
}

template <int dim>
PetscErrorCode QuasiStaticSolver<dim>::form_jacobian(SNES, Vec u, Mat, Mat P, void* ctx) {
  auto* self = static_cast<QuasiStaticSolver*>(ctx);
  return self->context_.guard.run([&] { self->op_.jacobian(u, 0.0, P); });
}

template <int dim>
std::optional<TangentStability> QuasiStaticSolver<dim>::stability_at(Vec u) {
  op_.jacobian(u, 0.0, J_.get());
  // A start vector with a component along every eigenvector (a fixed hash of the global
  // index, so the same on any number of ranks), zero on the constrained DOFs.
  petsc::Vector start = op_.space().create_vector();
  PetscInt first = 0, end = 0;
  WARPFEM_PETSC_CHECK(VecGetOwnershipRange(start.get(), &first, &end));
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(start.get(), &a));
  for (PetscInt i = first; i < end; ++i) a[i - first] = std::sin(12.9898 * static_cast<double>(i) + 0.5);
  WARPFEM_PETSC_CHECK(VecRestoreArray(start.get(), &a));
  op_.zero_constrained(start.get());
  return tangent_stability(J_.get(), start.get());
}

template <int dim>
void QuasiStaticSolver<dim>::check_stability(Vec u, double load, double increment, int reason) {
  stability_summary_.clear();
  if (!reference_) {
    petsc::Vector zero = op_.space().create_vector();
    reference_ = stability_at(zero.get());
    if (!reference_) return;
  }
  const std::optional<TangentStability> st = stability_at(u);
  if (!st) return;
  std::ostringstream summary;
  summary << "the equilibrium at s = " << load << " is "
          << (st->negative > 0 ? "unstable: its tangent stiffness has " + std::to_string(st->negative) +
                                     " negative eigenvalue(s), a buckling or bifurcation point lies behind"
                               : std::string("stable: its tangent stiffness is positive definite"))
          << "; eigenvalue nearest zero " << st->eigenvalue_nearest_zero
          << " (at s = 0: " << reference_->eigenvalue_nearest_zero << "), min det F = " << op_.min_det_F(u)
          << "; the step to s = " << load + increment << " failed with "
          << reason_text(static_cast<SNESConvergedReason>(reason));
  stability_summary_ = summary.str();
  if (st->negative > 0)
    log::warning(stability_summary_);
  else
    log::info("  ", stability_summary_);
}

template <int dim>
std::string QuasiStaticSolver<dim>::instability_of_iterate(Vec x, Vec u) {
  if (!(op_.min_det_F(x) > 0)) return "";
  auto fold = op_.min_det_F_in_cells(x);
  if (fold.min > 0) fold = op_.min_det_F_in_cells(u);
  if (fold.min > 0) return "";
  const std::optional<TangentStability> st = stability_at(x);
  if (!st || st->negative == 0) return "";
  std::ostringstream os;
  os << "Newton's iterates reach states whose tangent stiffness has " << st->negative
     << " negative eigenvalue(s), and the cell at x = (";
  for (int c = 0; c < dim; ++c) os << (c ? ", " : "") << fold.x(c);
  os << ") folds between its quadrature points (det F = " << fold.min << " there, min "
     << fold.cell_quadrature_min << " at its quadrature points)";
  return os.str();
}

template <int dim>
QuasiStaticReport QuasiStaticSolver<dim>::solve(Vec u,
                                                const std::function<void(const LoadStep&, Vec)>& on_step) {
  QuasiStaticReport report;
  const double nominal = 1.0 / stepping_.steps;
  double s = 0, ds = nominal;
  double stability_checked_at = -1;
  std::string previous_instability;  // of the last failed increment from s
  petsc::Vector trial;
  WARPFEM_PETSC_CHECK(VecDuplicate(u, trial.out()));
  while (s < 1.0 - 1e-14) {
    ds = std::min(ds, 1.0 - s);
    load_ = s + ds;
    Stopwatch watch;
    predict(u, load_, trial.get());
    context_.residuals.clear();
    context_.linear_iterations.clear();
    log::info("  load step s = ", std::setprecision(6), load_, " (Δs = ", ds, ")");
    const PetscErrorCode ierr = SNESSolve(snes_.get(), nullptr, trial.get());
    context_.guard.rethrow_if_failed();
    WARPFEM_PETSC_CHECK(ierr);
    SNESConvergedReason reason;
    WARPFEM_PETSC_CHECK(SNESGetConvergedReason(snes_.get(), &reason));
    if (reason > 0) {
      WARPFEM_PETSC_CHECK(VecCopy(trial.get(), u));
      LoadStep step;
      step.load = load_;
      step.increment = ds;
      WARPFEM_PETSC_CHECK(SNESGetIterationNumber(snes_.get(), &step.iterations));
      step.residuals = context_.residuals;
      step.linear_iterations = context_.linear_iterations;
      step.seconds = watch.seconds();
      report.steps.push_back(step);
      s = load_;
      log::info("  converged in ", step.iterations, " Newton iterations (", format_seconds(step.seconds),
                ")");
      if (on_step) on_step(step, u);
      if (step.iterations <= newton_.max_iterations / 3)
        ds = std::min(2 * ds, nominal);  // recover after cuts
      continue;
    }
    ++report.rejected_steps;
    if (stability_checked_at != s) {
      stability_checked_at = s;
      previous_instability.clear();
      check_stability(u, s, ds, reason);
    }
    // Two increments in a row from s (the second half as long) end with an indefinite tangent and
    // a cell folded between its quadrature points: the path loses stability at a fold that no
    // smaller increment gets past, so stop now instead of after many halvings.
    const std::string instability = instability_of_iterate(trial.get(), u);
    if (!instability.empty() && !previous_instability.empty()) {
      std::ostringstream os;
      os << "quasi-static solve stopped at load factor s = " << s
         << ": the equilibrium path loses stability there, which load stepping cannot follow; ";
      os << "beyond it, " << instability << "; ";
      os << stability_summary_;
      throw Error(
          os.str(),
          {.file = "",
           .key_path = "",
           .hint = "apply a smaller load, or change the model where it folds. Typically a free surface "
                   "that meets a clamped edge at a corner folds over there once the compression is large "
                   "enough (the solution is singular at such a corner, so a finer mesh reaches the fold "
                   "at a smaller load, and contact is not modelled); a rounded corner or a roller instead "
                   "of a clamp avoids it"});
    }
    previous_instability = instability;
    const double next = ds / 2;
    log::warning("load step to s = ", load_, " failed (", reason_text(reason),
                 "); retrying with Δs = ", next);
    if (next < stepping_.min_increment) {
      std::ostringstream os;
      os << "quasi-static solve failed: Newton did not converge from load factor s = " << s
         << " even with the "
         << "increment reduced to " << ds << " (" << reason_text(reason) << ")";
      if (!stability_summary_.empty()) os << "; " << stability_summary_;
      throw Error(os.str(),
                  {.file = "",
                   .key_path = "",
                   .hint = "use more load steps, a smaller minimum increment, a smaller load, or check "
                           "that the boundary conditions prevent rigid motions"});
    }
    ds = next;
  }
  report.domain_rejections = context_.domain_rejections;
  report.step_halvings = context_.step_halvings;
  // One more factorization, as cheap as a Newton step's when the linear solver is direct.
  if (newton_.pc_type == "lu" || newton_.pc_type == "cholesky") {
    const std::optional<TangentStability> st = stability_at(u);
    if (st) report.final_negative_eigenvalues = st->negative;
    if (st && st->negative > 0) {
      const auto fold = op_.min_det_F_in_cells(u);
      std::ostringstream os;
      os << "the equilibrium reached at s = 1 is unstable: its tangent stiffness has " << st->negative
         << " negative eigenvalue(s) (min det F = " << op_.min_det_F(u) << "; inside the cells " << fold.min
         << ", at x = (";
      for (int c = 0; c < dim; ++c) os << (c ? ", " : "") << fold.x(c);
      os << ")): a load step passed a point where the path loses stability, e.g. a free surface folding "
            "over at a clamped corner; more load steps show where";
      log::warning(os.str());
    }
  }
  return report;
}

template class QuasiStaticSolver<2>;
template class QuasiStaticSolver<3>;

}  // namespace warpfem::fem
