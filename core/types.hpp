#pragma once
// Scalar, point and Jacobian aliases shared by every module.
//
// Batches of points are stored structure-of-arrays: a Points<dim> is an
// N x dim column-major matrix, so all x coordinates are contiguous, then all
// y coordinates, ... This is the layout batched map evaluation vectorizes over.
// A Jacobians<dim> batch is N x (dim*dim); column i*dim + j holds d f_i / d x_j.

#include <Eigen/Core>
#include <cstdint>

namespace warpfem {

using Real = double;
using Index = std::int64_t;

template <int dim>
using Point = Eigen::Matrix<Real, dim, 1>;

template <int dim>
using Matrix = Eigen::Matrix<Real, dim, dim>;

template <int dim>
using Points = Eigen::Matrix<Real, Eigen::Dynamic, dim>;

template <int dim>
using Jacobians = Eigen::Matrix<Real, Eigen::Dynamic, dim * dim>;

using VectorX = Eigen::Matrix<Real, Eigen::Dynamic, 1>;
using MatrixX = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;

/// Reads the Jacobian of point `p` out of a batch.
template <int dim>
inline Matrix<dim> jacobian_at(const Jacobians<dim>& J, Index p) {
  Matrix<dim> m;
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) m(i, j) = J(p, i * dim + j);
  return m;
}

/// Stores the Jacobian `m` of point `p` into a batch.
template <int dim>
inline void set_jacobian_at(Jacobians<dim>& J, Index p, const Matrix<dim>& m) {
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) J(p, i * dim + j) = m(i, j);
}

}  // namespace warpfem
