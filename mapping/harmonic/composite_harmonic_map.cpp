#include "mapping/harmonic/composite_harmonic_map.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <iomanip>
#include <sstream>

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

void CompositeHarmonicMap::run(const Points<2>& x0, Points<2>* x, Jacobians<2>* J, VectorX* residual) const {
  const Index N = x0.rows();
  if (x) x->resize(N, 2);
  if (J) J->resize(N, 4);
  if (residual) residual->resize(N);
  const Real tolerance = inverse_tolerance();
  Point<2> z, y;
  Matrix<2> J0, J1;
  for (Index p = 0; p < N; ++p) {
    phi0_->eval_point(x0.row(p).transpose(), z, J ? &J0 : nullptr);
    const HarmonicInverse::Result r = inverse1_->apply(z, y, J ? &J1 : nullptr);
    if (residual)
      (*residual)(p) = r.residual;
    else if (!(r.residual <= tolerance)) {
      std::ostringstream what;
      what << std::setprecision(10) << "composite harmonic map (" << to_string(phi1_->method())
           << "): the inverse of φ1 does not converge at x0 = (" << x0(p, 0) << ", " << x0(p, 1)
           << "): residual " << std::setprecision(3) << r.residual << " > tolerance " << tolerance;
      throw Error(what.str(), {.file = "",
                               .key_path = "map.harmonic_method",
                               .hint = "φ1 misses the boundary of the intermediate polygon there; use "
                                       "\"harmonic_method\": \"fem\" or more \"boundary_nodes\""});
    }
    if (x) x->row(p) = y.transpose();
    if (J) set_jacobian_at<2>(*J, p, J1.inverse() * J0);
  }
}

Real CompositeHarmonicMap::inverse_tolerance() const {
  return kInverseTolerance * diameter(intermediate());
}

Real CompositeHarmonicMap::max_inverse_residual(const Points<2>& x0) const {
  Points<2> x;
  VectorX residual;
  run(x0, &x, nullptr, &residual);
  return residual.size() ? residual.maxCoeff() : 0.0;
}

void CompositeHarmonicMap::eval(const Points<2>& x0, Points<2>& x) const {
  run(x0, &x, nullptr, nullptr);
}
void CompositeHarmonicMap::jacobian(const Points<2>& x0, Jacobians<2>& J) const {
  run(x0, nullptr, &J, nullptr);
}
void CompositeHarmonicMap::eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const {
  run(x0, &x, &J, nullptr);
}
void CompositeHarmonicMap::eval_with_residual(const Points<2>& x0, Points<2>& x, Jacobians<2>& J,
                                              VectorX& residual) const {
  run(x0, &x, &J, &residual);
}

std::string CompositeHarmonicMap::describe() const {
  return "composite harmonic (" + to_string(phi0_->method()) + "), " + phi0_->domain().name() + " -> " +
         phi1_->domain().name() + " via " + intermediate().name();
}

CompositeHarmonicMap CompositeHarmonicMap::inverse() const {
  return CompositeHarmonicMap(phi1_, phi0_, diameter(phi0_->domain()) / diameter(phi1_->domain()) * seed_h_);
}

}  // namespace warpfem::mapping
