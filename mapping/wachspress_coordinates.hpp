#pragma once
// Wachspress (thesis eq. 1.5) and discrete harmonic (eq. 1.6) coordinates,
// both members of the three-point family (eq. 1.8, Floater–Hormann–Kós 2006)
//   w_i = (r_{i+1}^p A_{i−1} − r_i^p B_i + r_{i−1}^p A_i) / (A_{i−1} A_i),
// A_i = area(x, v_i, v_{i+1}), B_i = area(x, v_{i−1}, v_{i+1}); p = 0 gives
// Wachspress (numerator = area(v_{i−1}, v_i, v_{i+1}), constant), p = 2 discrete
// harmonic. Both have poles outside convex polygons, so both refuse concave ones.
//
// Evaluation is per point but batched (no allocation per point). The weights
// are rescaled by the smallest A_k, so points on an edge give the exact linear
// interpolant and points at a vertex the Kronecker delta.

#include <vector>

#include "core/polygon.hpp"
#include "core/types.hpp"
#include "mapping/barycentric_coordinates.hpp"

namespace warpfem::mapping {

/// Throws warpfem::Error unless `polygon` is convex (for Wachspress: strictly
/// convex, no collinear vertex, since its weight would vanish). The message
/// names the polygon, the coordinates and the first reflex/collinear vertex.
/// Uses exact orientation predicates.
void require_convex_for(const Polygon& polygon, Coordinates type);

/// φ and, if dphi_dx is not null, ∇φ (each N x n) of Wachspress or discrete harmonic
/// coordinates. Does not check convexity (call require_convex_for first).
void three_point_coordinates(Coordinates type, const PolygonArrays& polygon, const Points<2>& x, MatrixX& phi,
                             MatrixX* dphi_dx, MatrixX* dphi_dy);

/// Single-point version writing n values (and gradients if dx != null); `work` is reused.
void three_point_coordinates_at(Coordinates type, const PolygonArrays& polygon, Real x, Real y, Real* phi,
                                Real* dx, Real* dy, std::vector<Real>& work);

}  // namespace warpfem::mapping
