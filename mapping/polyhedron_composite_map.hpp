#pragma once
// Composite mean value map between polyhedra (thesis §4.4.2): for a vertex path
// v_i(t) (linear or intrinsic, mapping/polyhedron_vertex_path.hpp) and a partition
// 0 = t_0 < … < t_m = 1,
//   f = f_{m−1} ∘ … ∘ f_0,   f_k(x) = Σ_i φ_i(x; Ω_{t_k}) v_i(t_{k+1}),
// with φ the mean value coordinates of the intermediate polyhedron Ω_{t_k};
// J_f is the product of the step Jacobians J_k = Σ_i v_i(t_{k+1}) ∇φ_i^T.
//
// build_polyhedron_composite() chooses the partition adaptively (thesis
// Algorithm 1): an interval is halved while its step has det J_k ≤ ε on a
// sample of Ω_{t_k} clustered at every vertex, edge and face, and the map is
// refused, naming the interval and the smallest det J found, when that takes
// more than the allowed number of halvings.

#include <string>
#include <vector>

#include "core/polyhedron.hpp"
#include "mapping/map.hpp"
#include "mapping/polyhedron_mean_value_coordinates.hpp"
#include "mapping/polyhedron_vertex_path.hpp"

namespace warpfem::mapping {

class PolyhedronCompositeMap final : public Map<3> {
 public:
  /// Steps between the intermediate polyhedra at `times` (strictly increasing
  /// from 0 to 1) of the given vertex path; source and target must share the triangulation.
  PolyhedronCompositeMap(const Polyhedron& source, const Polyhedron& target, std::vector<Real> times,
                         VertexPathType path = VertexPathType::linear);
  PolyhedronCompositeMap(PolyhedronVertexPath path, std::vector<Real> times);

  void eval(const Points<3>& x0, Points<3>& x) const override;
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override;
  void eval_with_jacobian(const Points<3>& x0, Points<3>& x, Jacobians<3>& J) const override;
  std::string describe() const override;

  /// det J_k at x_k (N x m) for every step k; x and J (optional) receive f and J_f.
  void step_determinants(const Points<3>& x0, MatrixX& det_steps, Points<3>* x = nullptr,
                         Jacobians<3>* J = nullptr) const;
  Index steps() const { return static_cast<Index>(times_.size()) - 1; }
  const std::vector<Real>& times() const { return times_; }
  /// The intermediate polyhedron's vertices at time t.
  std::vector<Point<3>> vertices_at(Real t) const { return path_.vertices_at(t); }
  const PolyhedronVertexPath& path() const { return path_; }

  /// The backward map g: Ω1 → Ω0 (thesis §4.3): the same intermediate
  /// polyhedra in reverse, each step with the coordinates of Ω_{t_{k+1}};
  /// close to f⁻¹ but not equal to it.
  PolyhedronCompositeMap backward() const;

  /// f⁻¹(y) by Newton's method on f(x) = y started from the backward map.
  /// residual(p) = |f(x_p) − y_p| after at most `max_iterations` steps; the
  /// iteration stops once it is below `tolerance` times the source's size.
  void inverse(const Points<3>& y, Points<3>& x, VectorX& residual, Real tolerance = 1e-13,
               int max_iterations = 30) const;

 private:
  void run(const Points<3>& x0, Points<3>* x, Jacobians<3>* J, MatrixX* det_steps) const;
  PolyhedronVertexPath path_;
  std::vector<Real> times_;
  std::vector<PolyhedronArrays> cages_;  ///< Ω_{t_k}, k < m
  std::vector<MatrixX> targets_;         ///< vertices of Ω_{t_{k+1}} (n x 3)
};

/// Points inside `polyhedron` clustered at its vertices, edge points and face
/// points (offset inward by fractions of the local edge length), plus the
/// vertices of a coarse interior grid; `per_feature` offsets per feature.
Points<3> polyhedron_check_sample(const Polyhedron& polyhedron, int per_feature = 3);

struct PolyhedronPartitionOptions {
  Real epsilon = 1e-8;   ///< required det J_k (relative to the volume ratio of the step)
  int max_halvings = 8;  ///< per interval; the finest step is 2^-max_halvings
  VertexPathType vertex_path = VertexPathType::linear;
};

/// The composite map with an adaptive partition; throws warpfem::Error naming
/// the interval [t_k, t_k+1] and the smallest det J when no partition within
/// the allowed halvings makes every step orientation-preserving on the sample.
PolyhedronCompositeMap build_polyhedron_composite(const Polyhedron& source, const Polyhedron& target,
                                                  const PolyhedronPartitionOptions& options = {});

}  // namespace warpfem::mapping
