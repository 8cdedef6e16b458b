#pragma once
// Whether a Lagrange cell (the interpolant through its nodes' positions) folds:
// det of its Jacobian ≤ 0 at a node or on a lattice of step 1/8 on the
// reference cell (which contains the 5×5 lattice a viewer samples). On
// simplices of order ≤ 2 the Jacobian is affine in the barycentric
// coordinates, so det J is a polynomial of degree dim whose Bernstein
// coefficients follow from J at the vertices; when all of them are positive,
// det J > 0 on the whole cell and the lattice is not visited (the common case
// costs a few determinants instead of a few dozen Jacobians).

#include <array>
#include <vector>

#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

template <int dim>
class FoldCheck {
 public:
  static constexpr int max_nodes = dim == 2 ? 9 : 27;

  explicit FoldCheck(const LagrangeElement<dim>& element);

  /// x[k]: position of the cell's k-th node (element node order).
  bool folds(const Point<dim>* x) const;
  /// The same decision from the lattice alone (no Bernstein shortcut).
  bool folds_on_lattice(const Point<dim>* x) const;

 private:
  Matrix<dim> jacobian(const Point<dim>* x, Index p) const;
  bool bernstein_positive(const Point<dim>* x) const;

  int nloc_, nvert_;
  Index npoints_ = 0;
  std::vector<double> gradients_;                          ///< [check point][node][direction]
  std::vector<std::vector<std::array<int, dim>>> groups_;  ///< vertex tuples per Bernstein coefficient
};

}  // namespace warpfem::fem
