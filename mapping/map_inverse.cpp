#include "mapping/map_inverse.hpp"

#include <Eigen/LU>
#include <cmath>
#include <vector>

namespace warpfem::mapping {

template <int dim>
InverseReport invert(const Map<dim>& f, const Points<dim>& y, Points<dim>& x, const InverseOptions& options) {
  const Index n = y.rows();
  InverseReport report;
  Real scale = options.scale;
  if (!(scale > 0) && n > 0) scale = (y.colwise().maxCoeff() - y.colwise().minCoeff()).norm();
  if (!(scale > 0) && n > 0) scale = y.cwiseAbs().maxCoeff();  // one point, or all equal
  if (!(scale > 0)) scale = 1;
  const Real tol = options.tolerance * scale;
  report.tolerance = tol;
  std::vector<Index> active(static_cast<std::size_t>(n));
  for (Index p = 0; p < n; ++p) active[p] = p;
  VectorX residual(n);
  Points<dim> xa, fa, trial, ft;
  Jacobians<dim> Ja, Jt;
  for (int it = 0; it < options.max_iterations && !active.empty(); ++it) {
    report.iterations = it + 1;
    const Index m = static_cast<Index>(active.size());
    xa.resize(m, dim);
    for (Index k = 0; k < m; ++k) xa.row(k) = x.row(active[k]);
    f.eval_with_jacobian(xa, fa, Ja);
    // Newton step and its residual norm; drop converged points.
    Points<dim> step(m, dim);
    VectorX rnorm(m);
    std::vector<Index> next;
    for (Index k = 0; k < m; ++k) {
      const Point<dim> r = (fa.row(k) - y.row(active[k])).transpose();
      rnorm(k) = r.norm();
      step.row(k) = (jacobian_at<dim>(Ja, k).partialPivLu().solve(r)).transpose();
    }
    // Damping: halve the step until the residual decreases (at most 30 halvings).
    VectorX lambda = VectorX::Ones(m);
    std::vector<char> done(static_cast<std::size_t>(m), 0);
    for (int halving = 0; halving < 30; ++halving) {
      trial = xa - (lambda.asDiagonal() * step);
      f.eval(trial, ft);
      bool all = true;
      for (Index k = 0; k < m; ++k) {
        if (done[k]) continue;
        const double rn = (ft.row(k) - y.row(active[k])).norm();
        if (rn < rnorm(k) || rnorm(k) <= tol) {
          done[k] = 1;
          x.row(active[k]) = trial.row(k);
        } else {
          lambda(k) *= 0.5;
          all = false;
        }
      }
      if (all) break;
    }
    f.eval(x(active, Eigen::all), ft);
    for (Index k = 0; k < m; ++k) {
      const double rn = (ft.row(k) - y.row(active[k])).norm();
      residual(active[k]) = rn;
      if (!(rn <= tol)) next.push_back(active[k]);
    }
    active.swap(next);
  }
  if (report.iterations == 0) {  // nothing to do or max_iterations == 0
    Points<dim> fx;
    f.eval(x, fx);
    residual = (fx - y).rowwise().norm();
  }
  report.converged = n - static_cast<Index>(active.size());
  for (Index p = 0; p < n; ++p) {
    if (std::isnan(residual(p))) {  // a NaN is the worst there is
      report.worst = p, report.max_residual = residual(p);
      break;
    }
    if (report.worst < 0 || residual(p) > report.max_residual)
      report.worst = p, report.max_residual = residual(p);
  }
  return report;
}

template InverseReport invert<2>(const Map<2>&, const Points<2>&, Points<2>&, const InverseOptions&);
template InverseReport invert<3>(const Map<3>&, const Points<3>&, Points<3>&, const InverseOptions&);

}  // namespace warpfem::mapping
