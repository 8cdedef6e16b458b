#pragma once
// Inverse evaluation x = f⁻¹(y) of a bijective map by damped Newton iteration,
// batched over points: every iteration evaluates f and J_f once for all
// points still moving. A good initial guess (for composite maps: the backward
// map g ≈ f⁻¹ of thesis §4.3) makes it converge in a few steps.

#include "mapping/map.hpp"

namespace warpfem::mapping {

struct InverseOptions {
  Real tolerance = 1e-12;  ///< stop when ‖f(x) − y‖ ≤ tolerance · scale
  /// Length scale of the tolerance; 0 = the bounding-box diagonal of the batch y
  /// (so the test does not depend on the units or on where the origin is).
  Real scale = 0;
  int max_iterations = 50;
};

struct InverseReport {
  Index converged = 0;  ///< points that met the tolerance
  Real max_residual = 0;
  Index worst = -1;    ///< the point with the largest residual (-1 for an empty batch)
  Real tolerance = 0;  ///< the absolute tolerance used (tolerance · scale)
  int iterations = 0;
  bool all_converged(Index points) const { return converged == points; }
};

/// On entry `x` holds initial guesses, on exit f(x) ≈ y. Newton steps are damped
/// (halved) until the residual decreases. Points that miss the tolerance are
/// not converged: the report says how many and which is worst; callers must
/// treat them as failed, not as values of f⁻¹.
template <int dim>
InverseReport invert(const Map<dim>& f, const Points<dim>& y, Points<dim>& x,
                     const InverseOptions& options = {});

}  // namespace warpfem::mapping
