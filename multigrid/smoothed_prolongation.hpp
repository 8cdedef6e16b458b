#pragma once
// Smoothed prolongations with Galerkin level operators: the geometric
// interpolation P between nested levels, improved by one damped-Jacobi step
// on the finer level's operator,
//
//   P̃ = (I − ω D⁻¹A) P,   ω = damping / g,   g = Gershgorin's bound of D⁻¹A,
//
// and the coarser operator A_c = P̃ᵀ A P̃, level by level from the finest down
// (the same step smoothed aggregation takes on its tentative prolongator).
//
// Why: on strongly warped maps (the gear-like example) the pulled-back
// coefficient det J J⁻¹J⁻ᵀ is anisotropic in directions that change from
// cell to cell, and P, exact in Ω0, interpolates across the weak direction as
// readily as along it. The smoothing step bends each interpolating function
// along the operator, so the coarse spaces follow the coefficient; with
// symmetric-SOR smoothing the P1 V-cycle's iteration count then stays flat
// over the levels (P2's does not; docs/multigrid.md, BENCHMARKS.md).
//
// Rows without off-diagonal coupling (Dirichlet rows eliminated to the
// identity) keep their interpolation, so the eliminated block stays an
// injection and decoupled on every level.

#include <petscmat.h>

#include <vector>

#include "core/petsc/handles.hpp"

namespace warpfem::multigrid {

struct SmoothedLevels {
  /// [l] maps level l to level l + 1 (rows: level l + 1), l = 0 .. L − 1.
  std::vector<petsc::Matrix> interpolations;
  /// [l] = the Galerkin operator of level l, l = 0 .. L − 1 (the finest, level
  /// L, is the caller's matrix and not repeated here).
  std::vector<petsc::Matrix> operators;
};

/// The default damping ω·g: 4/3, the classical choice for D⁻¹A with spectrum in (0, g].
inline constexpr double kDefaultProlongationDamping = 4.0 / 3.0;

/// Smooths `prolongations` ([l] maps level l to l + 1, coarse to fine) from the
/// finest level down, starting from `finest` (the operator of level L =
/// prolongations.size()), and returns the smoothed interpolations and the
/// Galerkin operators of the coarser levels. `damping` in (0, 2) is ω·g.
/// Collective on the matrices' communicator. Throws warpfem::Error naming the
/// level for a non-positive diagonal entry in a coupled row, sizes that do not
/// chain, or a damping outside (0, 2).
SmoothedLevels smooth_prolongations(Mat finest, const std::vector<Mat>& prolongations,
                                    double damping = kDefaultProlongationDamping);

}  // namespace warpfem::multigrid
