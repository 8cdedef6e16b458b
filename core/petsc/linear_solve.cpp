#include "core/petsc/linear_solve.hpp"

#include <limits>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"
#include "core/timer.hpp"

namespace warpfem::petsc {

void collect_solve_outcome(KSP ksp, LinearSolveReport& report) {
  KSPConvergedReason reason;
  PetscInt its = 0;
  PetscReal rnorm = 0;
  KSPType kt = nullptr;
  PCType pt = nullptr;
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetConvergedReason(ksp, &reason));
  WARPFEM_PETSC_CHECK(KSPGetIterationNumber(ksp, &its));
  WARPFEM_PETSC_CHECK(KSPGetResidualNorm(ksp, &rnorm));
  WARPFEM_PETSC_CHECK(KSPGetType(ksp, &kt));
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp, &pc));
  WARPFEM_PETSC_CHECK(PCGetType(pc, &pt));
  report.iterations = static_cast<int>(its);
  report.residual_norm = rnorm;
  report.ksp_type = kt ? kt : "";
  report.pc_type = pt ? pt : "";
  report.converged_reason = KSPConvergedReasons[reason];
  report.converged = reason >= 0;  // negative reasons are PETSc's DIVERGED_*
}

void throw_if_diverged(const LinearSolveReport& report, const std::string& solver, const std::string& hint) {
  if (report.converged) return;
  throw Error(solver + " diverged after " + std::to_string(report.iterations) + " iterations: " +
                  report.converged_reason + " (residual norm " + std::to_string(report.residual_norm) + ")",
              {.file = "", .key_path = "solver", .hint = hint});
}

LinearSolveReport solve_linear_system(Mat A, Vec b, Vec x, const LinearSolveOptions& options) {
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(comm, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), A, A));
  PetscInt rows = 0, cols = 0;
  WARPFEM_PETSC_CHECK(MatGetSize(A, &rows, &cols));
  const bool direct = rows < options.direct_below;
  WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), direct ? KSPPREONLY : options.ksp_type.c_str()));
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, direct ? PCLU : options.pc_type.c_str()));
  if (direct) {
    int size = 1;
    MPI_Comm_size(comm, &size);
    if (size > 1) WARPFEM_PETSC_CHECK(PCSetType(pc, PCREDUNDANT));
  }
  WARPFEM_PETSC_CHECK(
      KSPSetTolerances(ksp.get(), options.rtol, options.atol, PETSC_DEFAULT, options.max_iterations));
  WARPFEM_PETSC_CHECK(KSPSetInitialGuessNonzero(ksp.get(), direct ? PETSC_FALSE : PETSC_TRUE));
  if (!options.prefix.empty()) WARPFEM_PETSC_CHECK(KSPSetOptionsPrefix(ksp.get(), options.prefix.c_str()));
  WARPFEM_PETSC_CHECK(KSPSetFromOptions(ksp.get()));

  LinearSolveReport report;
  Stopwatch watch;
  WARPFEM_PETSC_CHECK(KSPSetUp(ksp.get()));
  report.setup_seconds = watch.seconds();
  watch.reset();
  WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), b, x));
  report.solve_seconds = watch.seconds();

  collect_solve_outcome(ksp.get(), report);
  throw_if_diverged(report, "linear solver " + report.ksp_type + "/" + report.pc_type,
                    "raise solver.max_iterations, loosen solver.rtol, or choose another solver in "
                    "solver.petsc_options (e.g. \"-ksp_type gmres -pc_type lu\")");
  return report;
}

}  // namespace warpfem::petsc

namespace warpfem::petsc {

double estimate_condition_number(Mat A, int max_iterations) {
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(comm, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), A, A));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), KSPCG));
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, PCNONE));
  WARPFEM_PETSC_CHECK(KSPSetComputeSingularValues(ksp.get(), PETSC_TRUE));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp.get(), 1e-10, 1e-50, PETSC_DEFAULT, max_iterations));
  Vector b, x;
  WARPFEM_PETSC_CHECK(MatCreateVecs(A, x.out(), b.out()));
  PetscRandom rnd;
  WARPFEM_PETSC_CHECK(PetscRandomCreate(comm, &rnd));
  WARPFEM_PETSC_CHECK(PetscRandomSetSeed(rnd, 12345));
  WARPFEM_PETSC_CHECK(PetscRandomSeed(rnd));
  WARPFEM_PETSC_CHECK(VecSetRandom(b.get(), rnd));
  WARPFEM_PETSC_CHECK(PetscRandomDestroy(&rnd));
  WARPFEM_PETSC_CHECK(VecSet(x.get(), 0.0));
  WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), b.get(), x.get()));
  PetscReal smax = 0, smin = 0;
  WARPFEM_PETSC_CHECK(KSPComputeExtremeSingularValues(ksp.get(), &smax, &smin));
  return smin > 0 ? smax / smin : std::numeric_limits<double>::infinity();
}

}  // namespace warpfem::petsc
