#pragma once
// Cofactor matrix and determinant of small fixed-size matrices, closed form
// and branch-free: cof(A) = det(A) A^{-T}. Geometry uses it for J^{-T} and for
// the push-forward of facet normals (Nanson: n dA = cof(J_f) N dA0).

#include "core/types.hpp"

namespace warpfem {

template <int dim>
inline Matrix<dim> cofactor(const Matrix<dim>& a) {
  static_assert(dim == 1 || dim == 2 || dim == 3, "cofactor: dim must be 1, 2 or 3");
  Matrix<dim> c;
  if constexpr (dim == 1) {
    c(0, 0) = 1;
  } else if constexpr (dim == 2) {
    c << a(1, 1), -a(1, 0), -a(0, 1), a(0, 0);
  } else {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        c(i, j) = a(i1, j1) * a(i2, j2) - a(i1, j2) * a(i2, j1);
      }
  }
  return c;
}

/// det(a) from its cofactor matrix (expansion along the first row).
template <int dim>
inline double determinant_from_cofactor(const Matrix<dim>& a, const Matrix<dim>& cof) {
  double det = 0;
  for (int j = 0; j < dim; ++j) det += a(0, j) * cof(0, j);
  return det;
}

}  // namespace warpfem
