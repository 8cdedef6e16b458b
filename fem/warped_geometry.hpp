#pragma once
// Geometry of the warped cells f(T) at the quadrature points of a set of cells,
// computed once from batched calls of the map and cached (thesis eq. 9.2–9.4):
//   x0 = G(ξ) (point in Ω0), x = f(x0), J = J_f(x0) · J_G(ξ), J^{-T}, w |det J|.
// Assembly, Newton iterations and time steps read these arrays and never
// evaluate f again.
//
// Only what assembly reads is kept: x (2 numbers), J^{-T} (4) and w det J (1)
// per quadrature point; x0 and J_G are recomputed from the simple mesh when a
// caller needs them (cell_reference_geometry), and J_f = J · J_G⁻¹. The map is
// evaluated chunk by chunk so that its temporaries stay small.

#include <array>
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

  const Points<2>& physical_points() const { return x_; }  ///< f(x0) in Ω1
  const Jacobians<2>& inverse_transpose() const { return JinvT_; }
  const VectorX& JxW() const { return JxW_; }  ///< w_q |det J|

  /// x0 = G(ξ_q) and J_G(ξ_q) of the simple (unwarped) cell cells()[i], one row per
  /// quadrature point: recomputed from the mesh, not stored.
  void cell_reference_geometry(Index i, Points<2>& x0, Jacobians<2>& JG) const;

  /// Points per chunk of the batched map evaluation (bounds the temporaries).
  static constexpr Index chunk_points = Index{1} << 16;

 private:
  const Mesh<2>* mesh_;
  std::vector<Index> cells_;
  QuadratureRule<2> rule_;
  Index nq_ = 0;
  MatrixX geo_values_;
  std::array<MatrixX, 2> geo_gradients_;
  Points<2> x_;
  Jacobians<2> JinvT_;
  VectorX JxW_;
};

}  // namespace warpfem::fem
