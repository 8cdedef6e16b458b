#pragma once
// Reference-to-Ω0 geometry of a straight cell of the simple mesh:
// x0(ξ) = Σ N_k(ξ) v_k with the P1/Q1 shape functions N_k, and J_G = ∂x0/∂ξ.

#include <array>

#include "core/mesh/mesh.hpp"

namespace warpfem::fem {

/// Fills rows [offset, offset + nq) of x0 and J_G (row-major per point, see
/// Jacobians) for `cell`, from the P1/Q1 values N (nq x vertices) and
/// reference gradients dN at the nq reference points.
template <int dim>
void simple_cell_geometry(const Mesh<dim>& mesh, Index cell, Index nq, const MatrixX& N,
                          const std::array<MatrixX, dim>& dN, Points<dim>& x0, Jacobians<dim>& JG,
                          Index offset);

}  // namespace warpfem::fem
