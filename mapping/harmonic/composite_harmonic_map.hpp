#pragma once
// Composite harmonic map (thesis eq. 5.2): f = φ1⁻¹ ∘ φ0 : Ω0 → Ω1 with
// φ0: Ω0 → Λ, φ1: Ω1 → Λ harmonic onto one convex Λ. Values by
// y = φ1⁻¹(φ0(x)) (harmonic_inverse.hpp) and J_f(x) = J_φ1(y)⁻¹ · J_φ0(x).
// f maps vertex i of Ω0 to vertex i of Ω1; with fem (or exactly on ∂Ω0 for
// bem) it maps the edges onto each other as the boundary data prescribe.
//
// The inverse φ1⁻¹ can fail: the bem/mfs φ1 misses ∂Λ slightly, so points of Λ
// next to its boundary may have no preimage. Every evaluation knows its inverse
// residual; eval() and the Jacobians throw warpfem::Error naming the point when
// it exceeds inverse_tolerance(), eval_with_residual() reports it per point.

#include <memory>
#include <string>

#include "mapping/harmonic/harmonic_inverse.hpp"
#include "mapping/harmonic/harmonic_map.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping {

class CompositeHarmonicMap final : public Map<2> {
 public:
  /// φ0 and φ1 must have the same image Λ. seed_max_edge_length: the inverse's
  /// seed mesh of Ω1 for bem/mfs (0 = diameter(Ω1) / 50).
  CompositeHarmonicMap(HarmonicMapPtr phi0, HarmonicMapPtr phi1, Real seed_max_edge_length = 0);

  void eval(const Points<2>& x0, Points<2>& x) const override;
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override;
  void eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const override;
  void eval_with_residual(const Points<2>& x0, Points<2>& x, Jacobians<2>& J,
                          VectorX& residual) const override;
  /// kInverseTolerance · diameter(Λ).
  Real inverse_tolerance() const override;
  std::string describe() const override;

  /// A failed inverse: residual above this fraction of Λ's diameter.
  static constexpr Real kInverseTolerance = 1e-9;

  /// f⁻¹ = φ0⁻¹ ∘ φ1 (builds the inverse of φ0).
  CompositeHarmonicMap inverse() const;

  const HarmonicMap& phi0() const { return *phi0_; }
  const HarmonicMap& phi1() const { return *phi1_; }
  const Polygon& intermediate() const { return phi0_->image(); }
  /// Largest inverse residual |φ1(y) − φ0(x)| over the batch: how
  /// well the inverse was found. Re-evaluates f; eval() keeps no state.
  Real max_inverse_residual(const Points<2>& x0) const;

 private:
  /// Evaluates; residual(p) per point. Throws on the first failed inverse unless `residual` is given.
  void run(const Points<2>& x0, Points<2>* x, Jacobians<2>* J, VectorX* residual) const;

  HarmonicMapPtr phi0_, phi1_;
  Real seed_h_;
  std::shared_ptr<const HarmonicInverse> inverse1_;
};

}  // namespace warpfem::mapping
