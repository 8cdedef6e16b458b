#include "mapping/harmonic/composite_harmonic_map.hpp"

#include <Eigen/LU>
#include <algorithm>

#include "core/error.hpp"

namespace warpfem::mapping {

CompositeHarmonicMap::CompositeHarmonicMap(HarmonicMapPtr phi0, HarmonicMapPtr phi1,
                                           Real seed_max_edge_length)
    : phi0_(std::move(phi0)), phi1_(std::move(phi1)) {
  require(phi0_ && phi1_, "composite harmonic map: missing harmonic map");
  require(phi0_->image().vertices() == phi1_->image().vertices(),
          "composite harmonic map: φ0 and φ1 must share the intermediate polygon");
  seed_h_ = seed_max_edge_length > 0 ? seed_max_edge_length : diameter(phi1_->domain()) / 50;
  inverse1_ = std::make_shared<const HarmonicInverse>(phi1_, seed_h_);
}

Real CompositeHarmonicMap::run(const Points<2>& x0, Points<2>* x, Jacobians<2>* J) const {
  const Index N = x0.rows();
  if (x) x->resize(N, 2);
  if (J) J->resize(N, 4);
  Real worst = 0;
  Point<2> z, y;
  Matrix<2> J0, J1;
  for (Index p = 0; p < N; ++p) {
    phi0_->eval_point(x0.row(p).transpose(), z, J ? &J0 : nullptr);
    const HarmonicInverse::Result r = inverse1_->apply(z, y, J ? &J1 : nullptr);
    worst = std::max(worst, r.residual);
    if (x) x->row(p) = y.transpose();
    if (J) set_jacobian_at<2>(*J, p, J1.inverse() * J0);
  }
  return worst;
}

Real CompositeHarmonicMap::max_inverse_residual(const Points<2>& x0) const {
  Points<2> x;
  return run(x0, &x, nullptr);
}

void CompositeHarmonicMap::eval(const Points<2>& x0, Points<2>& x) const {
  run(x0, &x, nullptr);
}
void CompositeHarmonicMap::jacobian(const Points<2>& x0, Jacobians<2>& J) const {
  run(x0, nullptr, &J);
}
void CompositeHarmonicMap::eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const {
  run(x0, &x, &J);
}

std::string CompositeHarmonicMap::describe() const {
  return "composite harmonic (" + to_string(phi0_->method()) + "), " + phi0_->domain().name() + " -> " +
         phi1_->domain().name() + " via " + intermediate().name();
}

CompositeHarmonicMap CompositeHarmonicMap::inverse() const {
  return CompositeHarmonicMap(phi1_, phi0_, diameter(phi0_->domain()) / diameter(phi1_->domain()) * seed_h_);
}

}  // namespace warpfem::mapping
