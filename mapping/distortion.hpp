#pragma once
// Distortion measures of a map, computed from batches of Jacobians (any Map).
//
// With σ1 ≥ σ2 ≥ … the singular values of J_f at a point:
//   conformal distortion  σ1/σmin + σmin/σ1  (= 2 for a similarity, ≥ 2 always)
//   isometric distortion  max(σ1, 1/σmin)       (= 1 for a rigid motion, ≥ 1 always)
// Both are +inf where det J_f ≤ 0 (a fold has no meaningful distortion).
// In 2D the singular values have the closed form σ1,2 = |q ± r| with
// q = |(a+d, c−b)|/2, r = |(a−d, c+b)|/2 for J = [[a, b], [c, d]].

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/types.hpp"

namespace warpfem::mapping {

/// Largest and smallest singular value of the Jacobian of point p.
template <int dim>
inline std::pair<Real, Real> extreme_singular_values(const Jacobians<dim>& J, Index p) {
  if constexpr (dim == 2) {
    const Real a = J(p, 0), b = J(p, 1), c = J(p, 2), d = J(p, 3);
    const Real q = 0.5 * std::hypot(a + d, c - b), r = 0.5 * std::hypot(a - d, c + b);
    return {q + r, std::abs(q - r)};
  } else {
    const Matrix<dim> m = jacobian_at<dim>(J, p);
    const Eigen::SelfAdjointEigenSolver<Matrix<dim>> es(m.transpose() * m, Eigen::EigenvaluesOnly);
    return {std::sqrt(es.eigenvalues()(dim - 1)), std::sqrt(std::max(es.eigenvalues()(0), Real{0}))};
  }
}

/// det J_f for every point of the batch.
template <int dim>
inline VectorX jacobian_determinants(const Jacobians<dim>& J) {
  VectorX det(J.rows());
  if constexpr (dim == 2) {
    det = J.col(0).cwiseProduct(J.col(3)) - J.col(1).cwiseProduct(J.col(2));
  } else {
    for (Index p = 0; p < J.rows(); ++p) det(p) = jacobian_at<dim>(J, p).determinant();
  }
  return det;
}

/// Conformal and isometric distortion per point (+inf where det J ≤ 0).
template <int dim>
inline void distortion(const Jacobians<dim>& J, VectorX& conformal, VectorX& isometric) {
  const Index N = J.rows();
  const VectorX det = jacobian_determinants<dim>(J);
  conformal.resize(N);
  isometric.resize(N);
  constexpr Real inf = std::numeric_limits<Real>::infinity();
  for (Index p = 0; p < N; ++p) {
    if (!(det(p) > 0)) {
      conformal(p) = isometric(p) = inf;
      continue;
    }
    const auto [s1, s2] = extreme_singular_values<dim>(J, p);
    conformal(p) = s1 / s2 + s2 / s1;
    isometric(p) = std::max(s1, 1 / s2);
  }
}

/// Mean and maximum of a per-point measure.
struct DistortionStats {
  Real mean = 0;
  Real max = 0;
};

/// Everything a report needs about a sample of Jacobians.
struct DistortionSummary {
  Real min_det = 0;
  DistortionStats conformal;
  DistortionStats isometric;
  Index samples = 0;
};

/// Smallest / largest entry (plain loops: GCC 12 warns on Eigen's AVX-512 reductions).
inline Real min_entry(const Real* v, Index n) {
  Real m = std::numeric_limits<Real>::infinity();
  for (Index i = 0; i < n; ++i) m = std::min(m, v[i]);
  return m;
}
inline Real max_entry(const Real* v, Index n) {
  Real m = -std::numeric_limits<Real>::infinity();
  for (Index i = 0; i < n; ++i) m = std::max(m, v[i]);
  return m;
}

inline DistortionStats statistics(const VectorX& v) {
  if (v.size() == 0) return {};
  Real sum = 0;
  for (Index i = 0; i < v.size(); ++i) sum += v(i);
  return {sum / static_cast<Real>(v.size()), max_entry(v.data(), v.size())};
}

template <int dim>
inline DistortionSummary summarize_distortion(const Jacobians<dim>& J) {
  DistortionSummary s;
  s.samples = J.rows();
  if (J.rows() == 0) return s;
  VectorX c, i;
  distortion<dim>(J, c, i);
  const VectorX det = jacobian_determinants<dim>(J);
  s.min_det = min_entry(det.data(), det.size());
  s.conformal = statistics(c);
  s.isometric = statistics(i);
  return s;
}

}  // namespace warpfem::mapping
