#pragma once
// Mean value coordinates (Floater 2003; thesis eq. 1.7)
//   w_i = (tan(α_{i−1}/2) + tan(α_i/2)) / r_i,   φ_i = w_i / Σ_j w_j,
// where r_i = |v_i − x| and α_i is the signed angle at x spanned by the edge
// [v_i, v_{i+1}]. Defined for any simple polygon and any point; linear on the
// edges, Kronecker delta at the vertices, C^∞ inside.
//
// Batched over points (N x 2, SoA) with a vectorized kernel; points on or
// extremely close to the boundary are evaluated one at a time by a robust formula that
// rescales the weights by the singular factor (1/tan of the nearly-straight
// angle, and the distance to the nearest vertex), so results are finite and
// accurate everywhere, exactly on edges and at vertices included.

#include <vector>

#include "core/types.hpp"
#include "mapping/barycentric_coordinates.hpp"

namespace warpfem::mapping {

/// φ (N x n): column i holds φ_i at every point.
void mean_value_coordinates(const PolygonArrays& polygon, const Points<2>& x, MatrixX& phi);

/// φ and ∇φ (each N x n).
void mean_value_coordinates(const PolygonArrays& polygon, const Points<2>& x, MatrixX& phi, MatrixX& dphi_dx,
                            MatrixX& dphi_dy);

/// Robust evaluation at a single point (the boundary path of the batched
/// functions, exposed for tests). Writes n values to phi and, if dx/dy are not
/// null, n gradient components. `work` is resized as needed (reuse it).
void mean_value_coordinates_at(const PolygonArrays& polygon, Real x, Real y, Real* phi, Real* dx, Real* dy,
                               std::vector<Real>& work);

}  // namespace warpfem::mapping
