#include "fem/physics/elasticity/newton.hpp"

#include <iomanip>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::fem {
namespace {

PetscErrorCode monitor(SNES snes, PetscInt it, PetscReal norm, void* ctx) {
  auto* c = static_cast<NewtonContext*>(ctx);
  return c->guard.run([&] {
    c->residuals.push_back(norm);
    PetscInt total = 0;
    WARPFEM_PETSC_CHECK(SNESGetLinearSolveIterations(snes, &total));
    if (it > 0) c->linear_iterations.push_back(static_cast<int>(total - c->linear_total));
    c->linear_total = total;
    if (c->log_iterations) {
      std::ostringstream os;
      os << std::scientific << std::setprecision(3) << norm;
      log::info("    Newton ", it, ": |R| = ", os.str());
    }
  });
}

/// Backtracking on admissibility and on residual-norm or energy decrease (see newton.hpp).
PetscErrorCode line_search(SNESLineSearch ls, void* ctx) {
  auto* c = static_cast<NewtonContext*>(ctx);
  return c->guard.run([&] {
    SNES snes = nullptr;
    Vec X, F, Y, W, G;
    PetscReal xnorm, fnorm, ynorm;
    WARPFEM_PETSC_CHECK(SNESLineSearchGetSNES(ls, &snes));
    WARPFEM_PETSC_CHECK(SNESLineSearchGetVecs(ls, &X, &F, &Y, &W, &G));
    WARPFEM_PETSC_CHECK(SNESLineSearchGetNorms(ls, &xnorm, &fnorm, &ynorm));
    WARPFEM_PETSC_CHECK(VecNorm(X, NORM_2, &xnorm));
    WARPFEM_PETSC_CHECK(VecNorm(Y, NORM_2, &ynorm));
    // A full Newton correction below step_tolerance·|u| changes the state only at round-off level:
    // the residual cannot decrease any more (it is at its floor, which grows with the problem size),
    // so the step is taken and SNES's step test reports convergence.
    const bool at_round_off = ynorm <= c->step_tolerance * xnorm;
    std::optional<double> energy0;
    double lambda = 1.0;
    bool any_admissible = false;
    for (int halving = 0; halving <= c->max_halvings; ++halving, lambda *= 0.5) {
      WARPFEM_PETSC_CHECK(VecWAXPY(W, -lambda, Y, X));
      c->in_line_search = true;
      c->trial_rejected = false;
      const PetscErrorCode ierr = SNESComputeFunction(snes, W, G);
      c->in_line_search = false;
      WARPFEM_PETSC_CHECK(ierr);
      if (halving > 0) ++c->step_halvings;
      if (c->trial_rejected) continue;
      any_admissible = true;
      PetscReal gnorm = 0;
      WARPFEM_PETSC_CHECK(VecNorm(G, NORM_2, &gnorm));
      bool accept = gnorm <= (1 - 1e-4 * lambda) * fnorm || (at_round_off && halving == 0);
      if (!accept && c->objective) {
        if (!energy0) energy0 = c->objective(X);
        const std::optional<double> energy = c->objective(W);
        accept = energy0 && energy && *energy < *energy0;
      }
      if (!accept) continue;
      WARPFEM_PETSC_CHECK(VecCopy(W, X));
      WARPFEM_PETSC_CHECK(VecCopy(G, F));
      WARPFEM_PETSC_CHECK(VecNorm(X, NORM_2, &xnorm));
      // The step norm SNES tests is the full Newton correction: a short step after halvings says
      // nothing about the distance to the solution.
      WARPFEM_PETSC_CHECK(SNESLineSearchSetNorms(ls, xnorm, gnorm, ynorm));
      WARPFEM_PETSC_CHECK(SNESLineSearchSetLambda(ls, lambda));
      WARPFEM_PETSC_CHECK(SNESLineSearchSetReason(ls, SNES_LINESEARCH_SUCCEEDED));
      return;
    }
    WARPFEM_PETSC_CHECK(SNESLineSearchSetReason(
        ls, any_admissible ? SNES_LINESEARCH_FAILED_REDUCT : SNES_LINESEARCH_FAILED_DOMAIN));
  });
}

}  // namespace

void NewtonContext::reject(SNES snes) {
  ++domain_rejections;
  if (in_line_search)
    trial_rejected = true;
  else
    WARPFEM_PETSC_CHECK(SNESSetFunctionDomainError(snes));
}

void configure_newton(SNES snes, const NewtonOptions& o, NewtonContext& context, Mat jacobian) {
  context.log_iterations = o.log_iterations;
  WARPFEM_PETSC_CHECK(SNESSetOptionsPrefix(snes, o.prefix.c_str()));
  WARPFEM_PETSC_CHECK(SNESSetType(snes, SNESNEWTONLS));
  WARPFEM_PETSC_CHECK(SNESSetTolerances(snes, o.atol, o.rtol, o.step_tolerance, o.max_iterations, 100000));
  SNESLineSearch ls = nullptr;
  WARPFEM_PETSC_CHECK(SNESGetLineSearch(snes, &ls));
  context.max_halvings = o.max_halvings;
  context.step_tolerance = o.step_tolerance;
  if (o.line_search == "warpfem") {
    WARPFEM_PETSC_CHECK(SNESLineSearchSetType(ls, SNESLINESEARCHSHELL));
    WARPFEM_PETSC_CHECK(SNESLineSearchShellSetUserFunc(ls, line_search, &context));
  } else {
    WARPFEM_PETSC_CHECK(SNESLineSearchSetType(ls, o.line_search.c_str()));
  }
  WARPFEM_PETSC_CHECK(SNESMonitorSet(snes, monitor, &context, nullptr));
  KSP ksp = nullptr;
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(SNESGetKSP(snes, &ksp));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp, o.ksp_type.c_str()));
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp, &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, o.pc_type.c_str()));
  if (!o.factor_solver.empty() && (o.pc_type == "lu" || o.pc_type == "cholesky"))
    WARPFEM_PETSC_CHECK(PCFactorSetMatSolverType(pc, o.factor_solver.c_str()));
  if (o.configure_preconditioner) {
    require(jacobian != nullptr, "configure_newton: a custom preconditioner needs the Jacobian matrix");
    o.configure_preconditioner(ksp, jacobian);
  }
  WARPFEM_PETSC_CHECK(SNESSetFromOptions(snes));
}

std::string reason_text(SNESConvergedReason reason) {
  const char* text = SNESConvergedReasons[reason];
  return text ? text : std::to_string(static_cast<int>(reason));
}

}  // namespace warpfem::fem
