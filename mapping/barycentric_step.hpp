#pragma once
// One barycentric mapping step (thesis eq. 2.1), written as a displacement
//   f(x) = x + Σ_i φ_i(x) (w_i − v_i),     J_f = I + Σ_i (w_i − v_i) ⊗ ∇φ_i,
// from a source polygon (v_i) to a target polygon (w_i) with the same number of
// vertices. The displacement form is exact for identical polygons and keeps the
// rounding error proportional to the step size, which matters when thousands
// of small steps are composed.
//
// This is the building block of BarycentricMap and CompositeMeanValueMap: it
// evaluates one block of at most kStepBlock points given as SoA arrays.

#include <vector>

#include "core/polygon.hpp"
#include "mapping/barycentric_coordinates.hpp"

namespace warpfem::mapping {

inline constexpr int kStepBlock = 64;

class BarycentricStep {
 public:
  /// Throws warpfem::Error if the vertex counts differ or `coordinates` needs a
  /// convex source polygon and `source` is not convex.
  BarycentricStep(const Polygon& source, const std::vector<Point<2>>& target, Coordinates coordinates);

  /// Maps cnt ≤ kStepBlock points (x[p], y[p]) to (fx[p], fy[p]). If J is not
  /// null it receives the Jacobians as four arrays of stride kStepBlock:
  /// J[0*kStepBlock + p] = ∂f_x/∂x, J[1*..] = ∂f_x/∂y, J[2*..] = ∂f_y/∂x, J[3*..] = ∂f_y/∂y.
  /// Outputs must not alias inputs.
  void apply(const Real* x, const Real* y, int cnt, Real* fx, Real* fy, Real* J) const;

  /// Evaluates a whole batch (any size).
  void apply(const Points<2>& x0, Points<2>& x, Jacobians<2>* J) const;

  Coordinates coordinates() const { return coordinates_; }
  const PolygonArrays& source() const { return source_; }
  /// The vertex displacements w_i − v_i, as the kernel uses them.
  const std::vector<Real>& displacement_x() const { return ux_; }
  const std::vector<Real>& displacement_y() const { return uy_; }
  /// Largest vertex displacement |w_i − v_i| (d_k of thesis §4.2).
  Real max_displacement() const;

 private:
  /// The body of apply(); compiled for several instruction sets (see barycentric_step.cpp).
  void apply_kernel(const Real* x, const Real* y, int cnt, Real* fx, Real* fy, Real* J) const;
  Coordinates coordinates_;
  PolygonArrays source_;
  std::vector<Real> ux_, uy_;  ///< w_i − v_i
};

}  // namespace warpfem::mapping
