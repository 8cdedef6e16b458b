#pragma once
// Geometry of the warped cells f(T) at the quadrature points of a set of cells,
// computed once from one batched call of the map and cached (thesis eq. 9.2–9.4):
//   x0 = G(ξ) (point in Ω0), x = f(x0), J = J_f(x0) · J_G(ξ), det J, J^{-T}, w |det J|.
// Assembly, Newton iterations and time steps read these arrays and never
// evaluate f again.

#include <vector>

#include "fem/mesh.hpp"
#include "fem/quadrature.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

class WarpedGeometry {
 public:
  /// Throws warpfem::Error naming the cell and position if det J <= 0 anywhere.
  WarpedGeometry(const Mesh<2>& mesh, const std::vector<Index>& cells, const QuadratureRule<2>& rule,
                 const mapping::Map<2>& map);

  Index num_cells() const { return static_cast<Index>(cells_.size()); }
  Index points_per_cell() const { return nq_; }
  /// Flat index of quadrature point q of the i-th cell of cells().
  Index at(Index i, Index q) const { return i * nq_ + q; }
  const std::vector<Index>& cells() const { return cells_; }
  const QuadratureRule<2>& rule() const { return rule_; }

  const Points<2>& reference_points() const { return x0_; }  ///< x0 in Ω0
  const Points<2>& physical_points() const { return x_; }    ///< f(x0) in Ω1
  const Jacobians<2>& jacobian() const { return J_; }        ///< J = J_f J_G
  const Jacobians<2>& inverse_transpose() const { return JinvT_; }
  const VectorX& det() const { return detJ_; }
  const VectorX& map_det() const { return detJf_; }         ///< det J_f alone
  const Jacobians<2>& map_jacobian() const { return Jf_; }  ///< J_f alone
  const VectorX& JxW() const { return JxW_; }               ///< w_q |det J|

 private:
  std::vector<Index> cells_;
  QuadratureRule<2> rule_;
  Index nq_ = 0;
  Points<2> x0_, x_;
  Jacobians<2> J_, JinvT_, Jf_;
  VectorX detJ_, detJf_, JxW_;
};

}  // namespace warpfem::fem
