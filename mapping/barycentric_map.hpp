#pragma once
// A single barycentric mapping f(x) = Σ φ_i(x) v1_i (thesis eq. 2.1) from a source
// polygon Ω0 onto a target polygon Ω1. Linear on the edges, exact at the
// vertices, smooth inside — but not bijective in general (thesis §2.1.2): check
// with min_det_jacobian() or use CompositeMeanValueMap.

#include <string>

#include "core/polygon.hpp"
#include "mapping/barycentric_step.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping {

class BarycentricMap final : public Map<2> {
 public:
  /// Throws warpfem::Error on differing vertex counts or (Wachspress, discrete
  /// harmonic) a non-convex source.
  BarycentricMap(const Polygon& source, const Polygon& target,
                 Coordinates coordinates = Coordinates::mean_value);

  void eval(const Points<2>& x0, Points<2>& x) const override { step_.apply(x0, x, nullptr); }
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override;
  void eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const override {
    step_.apply(x0, x, &J);
  }
  std::string describe() const override;

  const BarycentricStep& step() const { return step_; }

 private:
  BarycentricStep step_;
  std::string source_name_, target_name_;
};

/// min over the sample of det J_f (a quick fold check for any 2D map).
Real min_det_jacobian(const Map<2>& map, const Points<2>& samples);

}  // namespace warpfem::mapping
