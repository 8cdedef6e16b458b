#pragma once
// Errors of a discrete solution against a reference solution computed on a
// finer level of the same nested hierarchy with the same map. Both live on Ω0,
// so they are compared at the same parameter points x0 — the same physical
// points f(x0) — without any geometric approximation.

#include "fem/physics/poisson.hpp"

namespace warpfem::fem {

/// L2 and H1-seminorm of u_h − u_ref over the warped domain (collective). In 3D
/// the reference mesh must be tetrahedral.
template <int dim>
ErrorNorms error_against_reference(const PoissonProblem<dim>& coarse, const PoissonProblem<dim>& reference);

}  // namespace warpfem::fem
