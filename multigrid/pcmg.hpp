#pragma once
// PETSc PCMG set-up from a nested hierarchy: our interpolation matrices, level
// operators by rediscretization (or Galerkin PᵀAP), Chebyshev–Jacobi smoothing
// and a direct coarse solve. The settings below are only defaults written
// into the KSP; every one of them is overridden by the options database under
// the KSP's prefix, e.g. -mg_levels_ksp_type richardson -mg_levels_pc_type sor,
// -pc_mg_cycle_type w, -pc_mg_type full, -mg_coarse_pc_type lu, -pc_mg_log.

#include <petscksp.h>

#include <vector>

namespace warpfem::multigrid {

struct MultigridSettings {
  enum class Cycle { v, w, f };
  /// chebyshev_jacobi: Chebyshev on D⁻¹A; chebyshev_sor: Chebyshev preconditioned
  /// by local symmetric SOR (about half the iterations on strongly warped maps,
  /// dearer per iteration); sor: Richardson with local symmetric SOR. `automatic`
  /// (the default): what GeometricMultigrid picks for its element, chebyshev_sor
  /// for scalar problems on quadratic tetrahedra (whose V-cycle iterations grow
  /// level by level with Jacobi on non-uniform meshes; docs/multigrid.md),
  /// chebyshev_jacobi otherwise;
  /// configure_pcmg itself treats it as chebyshev_jacobi.
  enum class Smoother { automatic, chebyshev_jacobi, chebyshev_sor, sor };
  enum class CoarseOperators { rediscretization, galerkin };
  Cycle cycle = Cycle::v;  ///< -pc_mg_cycle_type v|w; f is -pc_mg_type full
  Smoother smoother = Smoother::automatic;
  CoarseOperators coarse_operators = CoarseOperators::rediscretization;  ///< -pc_mg_galerkin
  /// Pre- and post-smoothing steps; 0: smoothing_steps_for() picks. Override: -mg_levels_ksp_max_it.
  int smoothing_steps = 0;
  /// Where the Chebyshev smoothers' target interval [0.1, 1.1]·λmax comes from:
  /// `estimate`: λmax of M⁻¹A from 10 CG steps per level at set-up (PETSc's way);
  /// `gershgorin`: [0.1, 1]·jacobi_gershgorin_bound(A_l), a guaranteed upper bound
  /// found in one pass over each level's matrix (chebyshev_jacobi with
  /// rediscretized levels only); `ssor`: [0.1, 1.1], since symmetric SOR
  /// (0 < ω < 2) preconditioning a symmetric positive definite A has λ(M⁻¹A)
  /// in (0, 1] (M − A is positive semidefinite); chebyshev_sor levels on one
  /// process only (across processes the sweeps are local, block Jacobi
  /// between them, and the bound fails: those levels are estimated);
  /// `automatic`: what the solver that builds the levels picks
  /// (PoissonMultigridSolver: gershgorin for order-1 elements with
  /// chebyshev_jacobi, ssor with chebyshev_sor, else estimate); configure_pcmg
  /// itself treats it as estimate.
  enum class ChebyshevBounds { automatic, estimate, gershgorin, ssor };
  ChebyshevBounds chebyshev_bounds = ChebyshevBounds::automatic;
  /// How levels that keep Chebyshev–Jacobi (after the options database has
  /// been read) run it. `petsc`: KSPCHEBYSHEV + PCJACOBI. `fused_double`: the
  /// same iteration in one pass over the matrix per step
  /// (fused_chebyshev_jacobi.hpp), its interval found at the smoother's set-up
  /// (Gershgorin's bound in the pass that takes the diagonal, or the same
  /// 10-step CG estimate PETSc makes). `fused_single` (default): that pass
  /// over a float copy of the level matrices' values. Both fused kernels also
  /// compute PCMG's level residuals; the Krylov method keeps the double matrix.
  enum class ChebyshevKernel { petsc, fused_double, fused_single };
  ChebyshevKernel chebyshev_kernel = ChebyshevKernel::fused_single;
  /// `geometric` (default): the nested spaces' interpolation, exact in Ω0.
  /// `smoothed`: that interpolation after one damped-Jacobi step on the finer
  /// operator, with Galerkin level operators built from the finest down
  /// (smoothed_prolongation.hpp); `coarse_operators` is then not used. For
  /// strongly warped maps, together with the chebyshev_sor smoother: the
  /// gear's P1 iteration counts stay flat over the levels. Poisson only.
  enum class Prolongation { geometric, smoothed };
  Prolongation prolongation = Prolongation::geometric;
};

/// The smoothing steps `settings` ask for: its own, or with 0 one Chebyshev–SOR
/// step (a symmetric sweep pair each; the V-cycles a second step saves do not
/// pay for it, measured in 2D and 3D) and two of any other smoother.
int smoothing_steps_for(const MultigridSettings& settings);

/// Makes the preconditioner of `ksp` a PCMG with interpolations.size() + 1
/// levels (level 0 coarsest). `interpolations[l]` maps level l to level l + 1
/// (rows: level l + 1). `operators` is either one matrix per level (coarse to
/// fine) or, with Galerkin coarse operators, possibly only the finest one; the
/// finest becomes the KSP's operator. The caller keeps the matrices alive as
/// long as the KSP (PETSc takes references). Call KSPSetFromOptions afterwards
/// so the options database can override these defaults.
/// Throws warpfem::Error for inconsistent sizes, PETSc failures via WARPFEM_PETSC_CHECK.
void configure_pcmg(KSP ksp, const std::vector<Mat>& interpolations, const std::vector<Mat>& operators,
                    const MultigridSettings& settings = {});

/// Call after KSPSetFromOptions; required with Gershgorin bounds, which it
/// supplies. A level that keeps Chebyshev–Jacobi becomes a fused smoother
/// that finds its interval at set-up ([0.1, 1]·g with Gershgorin bounds,
/// [0.1, 1.1]·λmax estimated otherwise), unless settings.chebyshev_kernel is
/// `petsc` or options name or monitor its KSP or PC; PETSc's smoother then
/// gets [0.1, 1]·jacobi_gershgorin_bound(A_l) with Gershgorin bounds and keeps
/// configure_pcmg's estimate otherwise. With Gershgorin bounds, a level whose
/// preconditioner the options database changed from Jacobi (e.g.
/// -mg_levels_pc_type sor) gets PETSc's eigenvalue estimate back, since the
/// bound is one for D⁻¹A only. With ssor bounds, a Chebyshev level
/// preconditioned by symmetric SOR with 0 < ω < 2 on a one-process
/// communicator gets [0.1, 1.1] and no estimate; other levels keep the
/// estimate. Levels where the options asked for an estimate or for
/// eigenvalues themselves are left alone.
void reconcile_chebyshev_bounds(KSP ksp, const MultigridSettings& settings);

}  // namespace warpfem::multigrid
