#pragma once
// Generalized barycentric coordinates on a polygon, evaluated for batches of points.
//
// All coordinates here are written as normalized weights (thesis eq. 1.4)
//   φ_i(x) = w_i(x) / W(x),   W = Σ_j w_j,
// with analytic gradients from the quotient rule (thesis eq. 4.2)
//   ∇φ_i = (∇w_i − φ_i ∇W) / W.
// Layout is structure-of-arrays: for N points and n vertices, `phi` is N x n
// column-major, so column i holds φ_i at all points contiguously.

#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "core/types.hpp"

namespace warpfem::mapping {

/// Which coordinates a barycentric map uses.
enum class Coordinates {
  mean_value,        ///< Floater 2003, eq. 1.7: any simple polygon
  wachspress,        ///< eq. 1.5: strictly convex polygons only
  discrete_harmonic  ///< eq. 1.6: convex polygons only
};

/// "mean_value" | "wachspress" | "discrete_harmonic"; throws warpfem::Error otherwise.
Coordinates parse_coordinates(const std::string& name);
std::string to_string(Coordinates c);

/// A polygon's vertices as two contiguous coordinate arrays (the SoA form the
/// kernels loop over) plus a length scale (bounding-box diagonal) for tolerances.
struct PolygonArrays {
  std::vector<Real> x, y;
  Real scale = 1;

  PolygonArrays() = default;
  explicit PolygonArrays(const Polygon& polygon);
  explicit PolygonArrays(const std::vector<Point<2>>& vertices);
  Index size() const { return static_cast<Index>(x.size()); }
};

/// Coordinates and their gradients at N points: each member is N x n, column i = vertex i.
struct BarycentricValues {
  MatrixX phi;      ///< φ_i(x_p)
  MatrixX dphi_dx;  ///< ∂φ_i/∂x (x_p); empty unless gradients were requested
  MatrixX dphi_dy;  ///< ∂φ_i/∂y (x_p)
};

/// Evaluates the coordinates of `type` w.r.t. `polygon` at the points `x` (N x 2).
/// Points on the boundary are fine: on an edge the coordinates are the linear
/// interpolants of its two vertices, at a vertex they are the Kronecker delta.
/// Throws warpfem::Error if `type` needs a convex polygon and `polygon` is not
/// (the message names the polygon and its first reflex vertex).
BarycentricValues barycentric_coordinates(Coordinates type, const Polygon& polygon, const Points<2>& x,
                                          bool with_gradients = true);

}  // namespace warpfem::mapping
