#pragma once
// Inverse evaluation x = f⁻¹(y) of a bijective map by damped Newton iteration,
// batched over points: every iteration evaluates f and J_f once for all
// points still moving. A good initial guess (for composite maps: the backward
// map g ≈ f⁻¹ of thesis §4.3) makes it converge in a few steps.

#include "mapping/map.hpp"

namespace warpfem::mapping {

struct InverseOptions {
  Real tolerance = 1e-12;  ///< stop when ‖f(x) − y‖ ≤ tolerance · (1 + ‖y‖)
  int max_iterations = 50;
};

struct InverseReport {
  Index converged = 0;  ///< points that met the tolerance
  Real max_residual = 0;
  int iterations = 0;
};

/// On entry `x` holds initial guesses, on exit f(x) ≈ y. Points whose Newton
/// step would leave the region where det J_f > 0 are damped (step halving).
template <int dim>
InverseReport invert(const Map<dim>& f, const Points<dim>& y, Points<dim>& x,
                     const InverseOptions& options = {});

}  // namespace warpfem::mapping
