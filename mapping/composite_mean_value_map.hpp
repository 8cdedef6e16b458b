#pragma once
// Composite barycentric mapping (thesis §4.2, Schneider et al. 2013)
//   f_τ = f_{m−1} ∘ … ∘ f_0,   f_k: Ω_{t_k} → Ω_{t_{k+1}} barycentric (mean value by default),
// for a partition τ = (0 = t_0 < … < t_m = 1) and intermediate polygons Ω_t from a
// VertexPath. Its Jacobian is the product J_f = J_{m−1}(x_{m−1}) ⋯ J_0(x_0) with
// x_{k+1} = f_k(x_k). A batch is processed block by block (kStepBlock points);
// each block runs through all steps while it stays in cache.
//
// This class only evaluates; it does not decide bijectivity. Use
// build_adaptive_composite() (adaptive_partition.hpp) to get a partition whose
// composite has det J_f > 0 on a dense sample, or give τ yourself.

#include <memory>
#include <string>
#include <vector>

#include "mapping/barycentric_step.hpp"
#include "mapping/map.hpp"
#include "mapping/vertex_path.hpp"

namespace warpfem::mapping {

class CompositeMeanValueMap final : public Map<2> {
 public:
  /// Steps between path.polygon_at(t_k). Throws warpfem::Error if τ is not
  /// strictly increasing from 0 to 1 or an intermediate polygon is invalid.
  CompositeMeanValueMap(const VertexPath& path, std::vector<Real> times,
                        Coordinates coordinates = Coordinates::mean_value);

  /// Steps between given polygons Ω_{t_0}, …, Ω_{t_m} (same vertex counts).
  CompositeMeanValueMap(std::vector<Polygon> polygons, std::vector<Real> times,
                        Coordinates coordinates = Coordinates::mean_value);

  void eval(const Points<2>& x0, Points<2>& x) const override;
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override;
  void eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const override;
  std::string describe() const override;

  /// The backward map g: Ω1 → Ω0 of thesis §4.3: the same intermediate polygons
  /// traversed in reverse, each step with coordinates of Ω_{t_{k+1}}. g ∘ f → id
  /// as the uniform partition is refined, but g ≠ f⁻¹ for finite m.
  CompositeMeanValueMap backward() const;

  /// Pushes the points through all steps; det_steps (N x m) receives det J_k at
  /// x_k, x (optional) f(x0), J (optional) J_f(x0).
  void step_determinants(const Points<2>& x0, MatrixX& det_steps, Points<2>* x = nullptr,
                         Jacobians<2>* J = nullptr) const;

  Index steps() const { return static_cast<Index>(steps_.size()); }
  const std::vector<Real>& times() const { return times_; }
  const std::vector<Polygon>& polygons() const { return polygons_; }
  const BarycentricStep& step(Index k) const { return steps_[static_cast<std::size_t>(k)]; }
  Coordinates coordinates() const { return coordinates_; }

 private:
  void run(const Points<2>& x0, Points<2>* x, Jacobians<2>* J, MatrixX* det_steps) const;

  std::vector<Polygon> polygons_;
  std::vector<Real> times_;
  Coordinates coordinates_;
  std::vector<BarycentricStep> steps_;
};

/// Uniform partition t_k = k/m.
std::vector<Real> uniform_partition(int m);

/// max_p ‖x_p − g(f(x_p))‖ over the sample: how far g is from f⁻¹.
Real round_trip_error(const Map<2>& f, const Map<2>& g, const Points<2>& x);

}  // namespace warpfem::mapping
