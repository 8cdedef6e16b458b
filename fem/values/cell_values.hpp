#pragma once
// The seam between the reference element and the warped geometry: shape
// functions, their physical gradients, JxW and x = f(x0) at the quadrature
// points of one cell at a time (deal.II's FEValues, Ferrite's CellValues).
//
// reinit() points the object at one cell of a GeometryChunk; it computes what
// the update flags ask for. The push-forward of shape gradients,
// ∇φ = J^{-T} ∇̂φ, is written here and nowhere else.

#include <Eigen/Core>
#include <Eigen/LU>

#include "fem/geometry/warped_geometry.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

template <int dim>
class CellValues {
 public:
  /// What reinit() computes beyond what the chunk holds (JxW, x, J^{-T}).
  enum Update : unsigned {
    update_gradients = 1u,         ///< physical shape gradients
    update_reference_points = 2u,  ///< x0 in Ω0 and J_f = J J_G⁻¹ (recomputed from the simple mesh)
  };
  using Gradients = Eigen::Matrix<double, dim, Eigen::Dynamic>;

  /// Values of `element` at the quadrature points of `geometry`.
  CellValues(const LagrangeElement<dim>& element, const WarpedGeometry<dim>& geometry, unsigned update);
  CellValues(const CellValues&) = delete;  // N_data_ points into N_ (a move keeps the buffer)
  CellValues& operator=(const CellValues&) = delete;
  CellValues(CellValues&&) = default;

  /// Cell i of `chunk`.
  void reinit(const GeometryChunk<dim>& chunk, Index i) {
    position_ = chunk.first_cell() + i;
    const Index base = chunk.at(i, 0);
    ld_ = chunk.leading_dimension();
    x_ = chunk.x_data() + base;
    J_ = chunk.inverse_transpose_data() + base;
    w_ = chunk.JxW_data() + base;
    if (update_ & update_gradients) push_forward();
    if (update_ & update_reference_points) geometry_->cell_reference_geometry(position_, x0_, JG_);
  }

  /// Index of the current cell in the geometry's cells().
  Index position() const { return position_; }
  /// The current cell's index in the mesh.
  Index cell() const { return geometry_->cells()[static_cast<std::size_t>(position_)]; }
  Index num_points() const { return nq_; }
  int num_dofs() const { return n_; }

  double JxW(Index q) const { return w_[q]; }
  /// x = f(x0) in Ω1.
  Point<dim> point(Index q) const {
    Point<dim> x;
    for (int d = 0; d < dim; ++d) x[d] = x_[d * ld_ + q];
    return x;
  }
  Matrix<dim> inverse_transpose(Index q) const {
    Matrix<dim> m;
    for (int r = 0; r < dim; ++r)
      for (int c = 0; c < dim; ++c) m(r, c) = J_[(r * dim + c) * ld_ + q];
    return m;
  }
  /// Entry k (= dim · row + column) of J^{-T}, without building the matrix.
  double inverse_transpose(Index q, int k) const { return J_[k * ld_ + q]; }

  double shape_value(Index q, int k) const { return N_data_[k * nq_ + q]; }
  /// (points x dofs) table of the shape values, the same for every cell.
  const MatrixX& shape_values() const { return N_; }
  /// ∂φ_k/∂ξ_d at reference point q (for kernels that fold J^{-T} into a metric).
  double reference_gradient(int d, Index q, int k) const { return dN_[static_cast<std::size_t>(d)](q, k); }
  /// Physical gradient ∇φ_k at point q (update_gradients).
  auto shape_gradient(Index q, int k) const { return grads_.col(q * n_ + k); }
  /// The dim x dofs block of all physical shape gradients at point q (update_gradients).
  auto shape_gradients(Index q) const { return grads_.middleCols(q * n_, n_); }

  /// Σ_k u_k φ_k at q for the cell's coefficients u.
  double value(Index q, const double* u) const {
    double s = 0;
    for (int k = 0; k < n_; ++k) s += u[k] * N_(q, k);
    return s;
  }
  /// Σ_k u_k ∇φ_k at q (update_gradients).
  Point<dim> gradient(Index q, const double* u) const {
    Point<dim> g = Point<dim>::Zero();
    for (int k = 0; k < n_; ++k) g += u[k] * shape_gradient(q, k);
    return g;
  }
  /// A vector field with dim interleaved components per node (u_k,i at dim k + i):
  /// its value at q.
  Point<dim> vector_value(Index q, const double* u) const {
    Point<dim> v = Point<dim>::Zero();
    for (int k = 0; k < n_; ++k) v += N_(q, k) * Eigen::Map<const Point<dim>>(u + dim * k);
    return v;
  }
  /// ... and its gradient (∇u)_{iJ} = Σ_k u_k,i ∂_J φ_k (update_gradients).
  Matrix<dim> vector_gradient(Index q, const double* u) const {
    Matrix<dim> g = Matrix<dim>::Zero();
    for (int k = 0; k < n_; ++k)
      g += Eigen::Map<const Point<dim>>(u + dim * k) * shape_gradient(q, k).transpose();
    return g;
  }

  /// x0 in Ω0 (update_reference_points).
  Point<dim> reference_point(Index q) const { return x0_.row(q).transpose(); }
  /// J_f(x0) = J J_G⁻¹ (update_reference_points).
  Matrix<dim> map_jacobian(Index q) const {
    return inverse_transpose(q).transpose().inverse() * jacobian_at<dim>(JG_, q).inverse();
  }

 private:
  void push_forward() {
    for (Index q = 0; q < nq_; ++q) {
      const Matrix<dim> JinvT = inverse_transpose(q);
      grads_.middleCols(q * n_, n_).noalias() = JinvT * reference_gradients_.middleCols(q * n_, n_);
    }
  }

  const WarpedGeometry<dim>* geometry_;
  unsigned update_;
  Index nq_;
  int n_;
  MatrixX N_;                       // (points x dofs)
  std::array<MatrixX, dim> dN_;     // reference gradients, (points x dofs) per direction
  Gradients reference_gradients_;   // dim x (points · dofs): column q n + k is ∇̂φ_k(ξ_q)
  Gradients grads_;                 // the same, pushed forward
  const double* N_data_ = nullptr;  // N_'s column-major data: (q, k) at k nq + q
  // The current cell's arrays in the chunk (leading dimension ld_).
  const double *x_ = nullptr, *J_ = nullptr, *w_ = nullptr;
  Index ld_ = 0;
  Index position_ = 0;
  Points<dim> x0_;
  Jacobians<dim> JG_;
};

}  // namespace warpfem::fem
