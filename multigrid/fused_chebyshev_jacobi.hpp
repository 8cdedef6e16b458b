#pragma once
// Chebyshev–Jacobi smoothing with one pass over the matrix per step.
//
// PETSc's KSPCHEBYSHEV with PCJACOBI spends each step in a matrix-vector
// product plus four vector passes (residual, diagonal scaling, the three-term
// recurrence, the update) and copies. The fused form runs the same
// first-kind Chebyshev iteration on [emin, emax] (eigenvalues of D⁻¹A) row
// by row, with two iterates instead of a direction vector:
//
//   x_{k+1,i} = x_{k,i} + c1·(x_{k,i} − x_{k−1,i}) + c2·(b_i − (A x_k)_i) / a_ii,
//
// reading each row, b_i, 1/a_ii and x_{k−1,i} once and writing x_{k+1,i}
// over x_{k−1,i}; a zero initial guess costs no product in the first step.
// With `single` precision the values come from a float copy (vectors and
// sums stay double): 8 instead of 12 bytes per nonzero. A smoother needs
// about one correct digit, and the outer Krylov method keeps the double
// matrix, so the solution's accuracy is unchanged (the same split as
// deal.II's single-precision multigrid under a double CG).
// use_fused_residual() lets PCMG's level residual use the same data.
//
// It is a PCSHELL under KSPRICHARDSON that implements PETSc's "Richardson
// application" hook (as PCSOR does), which is how PCMG runs its smoothers:
// Richardson's iteration count is the number of Chebyshev steps.
// Matrices: MATSEQAIJ, or MATMPIAIJ (diagonal and off-diagonal blocks; the
// off-rank values of x are gathered once per step).

#include <petscksp.h>

namespace warpfem::multigrid {

enum class SmootherPrecision { double_precision, single };

/// Where the scale g of the Chebyshev interval comes from, at set-up.
/// `gershgorin`: max_i Σ_j |a_ij| / a_ii ≥ λmax(D⁻¹A), found in the pass that
/// takes the diagonal (chebyshev_bounds.hpp says why it suits first-order
/// stiffness matrices). `cg_estimate`: λmax(D⁻¹A) estimated by 10 steps of
/// Jacobi-preconditioned CG from a fixed random right-hand side, as PETSc's
/// Chebyshev does (for P2/Q2, where Gershgorin overshoots by 30–130 %).
enum class ChebyshevBound { gershgorin, cg_estimate };

struct FusedChebyshevOptions {
  /// Target interval [lower, upper]·g of D⁻¹A's spectrum.
  double lower = 0.1, upper = 1.0;
  ChebyshevBound bound = ChebyshevBound::gershgorin;
  SmootherPrecision precision = SmootherPrecision::single;
};

/// Makes `smoother` (its operators set) a fused Chebyshev–Jacobi smoother:
/// KSPRICHARDSON with unit scale and a shell PC. Each KSPSolve runs the KSP's
/// maximum iteration count of Chebyshev steps from the given (or zero)
/// initial guess: the iteration of KSPCHEBYSHEV + PCJACOBI with
/// KSPChebyshevSetEigenvalues(upper·g, lower·g). The diagonal, g and the
/// float values are taken at the PC's set-up (again whenever the operator
/// changes); single precision falls back to double on a rank whose values
/// exceed float's range. Throws warpfem::Error for a bad interval; the set-up
/// fails with a message for a matrix that is not AIJ or a diagonal entry that
/// is not positive.
void set_fused_chebyshev_jacobi(KSP smoother, const FusedChebyshevOptions& options = {});

/// Makes PCMG compute the residual b − A_l x of `level`, whose smoother must be
/// fused, with that smoother's matrix values in one pass (the float copy in
/// single precision) instead of MatResidual on the double matrix. The V-cycle
/// then smooths and restricts residuals of the same (rounded) operator; the
/// outer Krylov method keeps the double matrix.
void use_fused_residual(PC mg, PetscInt level);

/// True if `smoother` was made fused by set_fused_chebyshev_jacobi (and nothing
/// has replaced its PC since).
bool is_fused_chebyshev_jacobi(KSP smoother);

/// What the last set-up of a fused smoother found (for tests and reports).
struct FusedChebyshevState {
  double emin = 0, emax = 0;
  bool single_precision = false;
};
FusedChebyshevState fused_chebyshev_state(KSP smoother);

}  // namespace warpfem::multigrid
