#pragma once
// Errors of a discrete solution against a reference solution.
//
// error_against_reference: the reference is computed on a finer level of the
// same nested hierarchy with the same map. Both live on Ω0, so they are
// compared at the same parameter points x0 — the same physical points f(x0) —
// without any geometric approximation.
//
// straight_mesh_error_against_reference: the solution lives on straight cells
// of a mesh of the exact domain f(Ω0) itself (the identity map, e.g. a TetGen
// mesh of the target polyhedron), with no common parametrization: the error is
// integrated on the reference's quadrature points x = f(x0), where the straight
// solution is found by locating x in its mesh.

#include "fem/physics/poisson.hpp"

namespace warpfem::fem {

/// L2 and H1-seminorm of u_h − u_ref over the warped domain (collective). In 3D
/// the reference mesh must be tetrahedral.
template <int dim>
ErrorNorms error_against_reference(const PoissonProblem<dim>& coarse, const PoissonProblem<dim>& reference);

/// L2 and H1-seminorm of u_h − u_ref over the reference's warped domain, for a
/// `straight` problem with the identity map whose mesh covers that domain
/// (collective; triangles in 2D, tetrahedra in 3D). The integrand is smooth only
/// piecewise inside a reference cell (the straight cells' faces cross it), so the
/// reference should be finer than the straight mesh. Throws warpfem::Error on
/// every rank when the straight problem's map is not the identity or a
/// quadrature point of the reference lies outside the straight mesh.
template <int dim>
ErrorNorms straight_mesh_error_against_reference(const PoissonProblem<dim>& straight,
                                                 const PoissonProblem<dim>& reference);

}  // namespace warpfem::fem
