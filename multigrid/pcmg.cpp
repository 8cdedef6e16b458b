#include "multigrid/pcmg.hpp"

#include <string>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "multigrid/chebyshev_bounds.hpp"
#include "multigrid/fused_chebyshev_jacobi.hpp"

namespace warpfem::multigrid {
namespace {

void configure_smoother(KSP smoother, const MultigridSettings& s) {
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &pc));
  if (s.smoother != MultigridSettings::Smoother::sor) {
    WARPFEM_PETSC_CHECK(KSPSetType(smoother, KSPCHEBYSHEV));
    if (s.smoother != MultigridSettings::Smoother::chebyshev_sor) {  // Jacobi, also when automatic
      WARPFEM_PETSC_CHECK(PCSetType(pc, PCJACOBI));
    } else {
      WARPFEM_PETSC_CHECK(PCSetType(pc, PCSOR));
      WARPFEM_PETSC_CHECK(PCSORSetSymmetric(pc, SOR_LOCAL_SYMMETRIC_SWEEP));
    }
    // Target [0.1, 1.1] λmax of M⁻¹A, λmax from a few CG iterations at set-up.
    WARPFEM_PETSC_CHECK(KSPChebyshevEstEigSet(smoother, 0.0, 0.1, 0.0, 1.1));
    KSP est = nullptr;
    WARPFEM_PETSC_CHECK(KSPChebyshevEstEigGetKSP(smoother, &est));
    if (est) WARPFEM_PETSC_CHECK(KSPSetType(est, KSPCG));
  } else {
    WARPFEM_PETSC_CHECK(KSPSetType(smoother, KSPRICHARDSON));
    WARPFEM_PETSC_CHECK(PCSetType(pc, PCSOR));
    WARPFEM_PETSC_CHECK(PCSORSetSymmetric(pc, SOR_LOCAL_SYMMETRIC_SWEEP));
  }
}

/// True if the options database has `name` under the smoother's prefix.
bool has_option(KSP smoother, const char* name) {
  const char* prefix = nullptr;
  PetscBool set = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(KSPGetOptionsPrefix(smoother, &prefix));
  WARPFEM_PETSC_CHECK(PetscOptionsHasName(nullptr, prefix, name, &set));
  return set == PETSC_TRUE;
}

/// True for PCJACOBI scaling by the diagonal itself (not its absolute value,
/// row maxima or row sums), i.e. the D of Gershgorin's bound on D⁻¹A.
bool plain_jacobi(PC jacobi) {
  PCJacobiType type = PC_JACOBI_DIAGONAL;
  PetscBool abs = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PCJacobiGetType(jacobi, &type));
  WARPFEM_PETSC_CHECK(PCJacobiGetUseAbs(jacobi, &abs));
  return type == PC_JACOBI_DIAGONAL && !abs;
}

/// True if `pc` is symmetric SOR with 0 < ω < 2 and the smoother runs on one
/// process, where λ(M⁻¹A) ≤ 1 for every symmetric positive definite A.
bool symmetric_sor_on_one_process(KSP smoother, PC pc) {
  PetscBool sor = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCSOR, &sor));
  if (!sor) return false;
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(smoother), &comm));
  int size = 1;
  MPI_Comm_size(comm, &size);
  MatSORType sweep{};
  PetscReal omega = 0;
  WARPFEM_PETSC_CHECK(PCSORGetSymmetric(pc, &sweep));
  WARPFEM_PETSC_CHECK(PCSORGetOmega(pc, &omega));
  const bool symmetric = (sweep & SOR_SYMMETRIC_SWEEP) == SOR_SYMMETRIC_SWEEP ||
                         (sweep & SOR_LOCAL_SYMMETRIC_SWEEP) == SOR_LOCAL_SYMMETRIC_SWEEP;
  return size == 1 && symmetric && omega > 0 && omega < 2;
}

}  // namespace

int smoothing_steps_for(const MultigridSettings& settings) {
  if (settings.smoothing_steps > 0) return settings.smoothing_steps;
  return settings.smoother == MultigridSettings::Smoother::chebyshev_sor ? 1 : 2;
}

void configure_pcmg(KSP ksp, const std::vector<Mat>& interpolations, const std::vector<Mat>& operators,
                    const MultigridSettings& settings) {
  const int levels = static_cast<int>(interpolations.size()) + 1;
  const bool galerkin = settings.coarse_operators == MultigridSettings::CoarseOperators::galerkin;
  if (operators.empty() || (!galerkin && static_cast<int>(operators.size()) != levels))
    throw Error("configure_pcmg: " + std::to_string(operators.size()) + " level operators for " +
                    std::to_string(levels) + " levels",
                {.file = "",
                 .key_path = "",
                 .hint = "pass one operator per level, or only the finest with Galerkin coarse operators"});
  require(settings.smoothing_steps >= 0, "configure_pcmg: smoothing_steps must be >= 0 (0: automatic)");
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(ksp), &comm));
  int size = 1;
  MPI_Comm_size(comm, &size);

  Mat finest = operators.back();
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp, finest, finest));
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp, &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, PCMG));
  WARPFEM_PETSC_CHECK(PCMGSetLevels(pc, levels, nullptr));
  WARPFEM_PETSC_CHECK(
      PCMGSetType(pc, settings.cycle == MultigridSettings::Cycle::f ? PC_MG_FULL : PC_MG_MULTIPLICATIVE));
  WARPFEM_PETSC_CHECK(
      PCMGSetCycleType(pc, settings.cycle == MultigridSettings::Cycle::w ? PC_MG_CYCLE_W : PC_MG_CYCLE_V));
  WARPFEM_PETSC_CHECK(PCMGSetGalerkin(pc, galerkin ? PC_MG_GALERKIN_BOTH : PC_MG_GALERKIN_NONE));
  WARPFEM_PETSC_CHECK(PCMGSetNumberSmooth(pc, smoothing_steps_for(settings)));
  for (int l = 1; l < levels; ++l) WARPFEM_PETSC_CHECK(PCMGSetInterpolation(pc, l, interpolations[l - 1]));

  const bool gershgorin = settings.chebyshev_bounds == MultigridSettings::ChebyshevBounds::gershgorin;
  const bool jacobi = settings.smoother == MultigridSettings::Smoother::chebyshev_jacobi ||
                      settings.smoother == MultigridSettings::Smoother::automatic;
  if (gershgorin && (!jacobi || galerkin))
    throw Error(
        "Gershgorin bounds for the Chebyshev smoothers need the smoother chebyshev_jacobi and "
        "rediscretized level operators",
        {.file = "",
         .key_path = "solver.multigrid.chebyshev_bounds",
         .hint = "use \"estimate\" (or \"auto\") with this smoother or with Galerkin coarse operators"});
  for (int l = 1; l < levels; ++l) {
    KSP smoother = nullptr;
    WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, l, &smoother));
    if (!galerkin) WARPFEM_PETSC_CHECK(KSPSetOperators(smoother, operators[l], operators[l]));
    configure_smoother(smoother, settings);
    // No Krylov estimate: reconcile_chebyshev_bounds targets [0.1, 1]·g with
    // g >= λmax(D⁻¹A_l) guaranteed, once the options are known.
    if (gershgorin) WARPFEM_PETSC_CHECK(KSPChebyshevEstEigSet(smoother, 0.0, 0.0, 0.0, 0.0));
  }
  KSP coarse = nullptr;
  WARPFEM_PETSC_CHECK(PCMGGetCoarseSolve(pc, &coarse));
  if (!galerkin && levels > 1) WARPFEM_PETSC_CHECK(KSPSetOperators(coarse, operators[0], operators[0]));
  WARPFEM_PETSC_CHECK(KSPSetType(coarse, KSPPREONLY));
  PC coarse_pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(coarse, &coarse_pc));
  // Serial: LU (the eliminated Dirichlet rows keep the coarse matrix SPD and nonsingular).
  // Parallel: every rank factors a full copy (the coarse level is small).
  WARPFEM_PETSC_CHECK(PCSetType(coarse_pc, size == 1 ? PCLU : PCREDUNDANT));
}

void reconcile_chebyshev_bounds(KSP ksp, const MultigridSettings& settings) {
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp, &pc));
  PetscBool is_mg = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCMG, &is_mg));
  if (!is_mg) return;
  using Kernel = MultigridSettings::ChebyshevKernel;
  const bool gershgorin = settings.chebyshev_bounds == MultigridSettings::ChebyshevBounds::gershgorin;
  PetscInt levels = 0;
  WARPFEM_PETSC_CHECK(PCMGGetLevels(pc, &levels));
  for (PetscInt l = 1; l < levels; ++l) {
    KSP smoother = nullptr, estimator = nullptr;
    PC spc = nullptr;
    PetscBool chebyshev = PETSC_FALSE, jacobi = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, l, &smoother));
    // PCMG reads the level options only in PCSetUp; read them now to see what they changed.
    WARPFEM_PETSC_CHECK(KSPSetFromOptions(smoother));
    WARPFEM_PETSC_CHECK(
        PetscObjectTypeCompare(reinterpret_cast<PetscObject>(smoother), KSPCHEBYSHEV, &chebyshev));
    if (!chebyshev) continue;
    WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &spc));
    WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(spc), PCJACOBI, &jacobi));
    if (has_option(smoother, "-ksp_chebyshev_esteig") || has_option(smoother, "-ksp_chebyshev_eigenvalues"))
      continue;
    const bool plain = jacobi && plain_jacobi(spc);
    // PETSc's smoother stays where options name it (PCMG's set-up reads them again, so a
    // fused level would be turned back into KSPCHEBYSHEV or PCJACOBI alone) or monitor its
    // steps (the fused smoother runs all steps in one call).
    const bool named = has_option(smoother, "-ksp_type") || has_option(smoother, "-pc_type") ||
                       has_option(smoother, "-ksp_monitor");
    if (plain && !named && settings.chebyshev_kernel != Kernel::petsc) {
      FusedChebyshevOptions fused{.lower = 0.1, .upper = 1.0, .bound = ChebyshevBound::gershgorin};
      if (!gershgorin) fused = {.lower = 0.1, .upper = 1.1, .bound = ChebyshevBound::cg_estimate};
      fused.precision = settings.chebyshev_kernel == Kernel::fused_single
                            ? SmootherPrecision::single
                            : SmootherPrecision::double_precision;
      set_fused_chebyshev_jacobi(smoother, fused);
      // Galerkin levels get their operators only in PCMG's set-up; they keep MatResidual.
      PetscBool has_operator = PETSC_FALSE;
      WARPFEM_PETSC_CHECK(KSPGetOperatorsSet(smoother, &has_operator, nullptr));
      if (has_operator) use_fused_residual(pc, l);
      continue;
    }
    if (settings.chebyshev_bounds == MultigridSettings::ChebyshevBounds::ssor) {
      if (symmetric_sor_on_one_process(smoother, spc)) {
        WARPFEM_PETSC_CHECK(KSPChebyshevEstEigSet(smoother, 0.0, 0.0, 0.0, 0.0));
        WARPFEM_PETSC_CHECK(KSPChebyshevSetEigenvalues(smoother, 1.1, 0.1));
      }
      continue;
    }
    if (!gershgorin) continue;  // configure_pcmg's estimate stands
    // Chebyshev estimates by default when it has no eigenvalues; they come below.
    WARPFEM_PETSC_CHECK(KSPChebyshevEstEigSet(smoother, 0.0, 0.0, 0.0, 0.0));
    if (plain) {
      Mat A = nullptr;
      WARPFEM_PETSC_CHECK(KSPGetOperators(smoother, &A, nullptr));
      const double g = jacobi_gershgorin_bound(A);
      WARPFEM_PETSC_CHECK(KSPChebyshevSetEigenvalues(smoother, g, 0.1 * g));
      continue;
    }
    WARPFEM_PETSC_CHECK(KSPChebyshevEstEigSet(smoother, 0.0, 0.1, 0.0, 1.1));
    WARPFEM_PETSC_CHECK(KSPChebyshevEstEigGetKSP(smoother, &estimator));
    if (estimator) WARPFEM_PETSC_CHECK(KSPSetType(estimator, KSPCG));
  }
}

}  // namespace warpfem::multigrid
