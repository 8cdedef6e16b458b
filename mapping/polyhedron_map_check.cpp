#include "mapping/polyhedron_map_check.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>

#include "mapping/distortion.hpp"

namespace warpfem::mapping {

/// Relative round-trip error above which the inverse counts as failed.
constexpr Real kRoundTripTolerance = 1e-9;

std::string PolyhedronMapCheck::summary() const {
  std::ostringstream os;
  os << std::setprecision(4) << "min det J_f = " << min_det << " on " << samples
     << " samples clustered at every vertex, edge and face; images inside the target; max |f^-1(f(x)) - x| = "
     << max_round_trip << " (relative)";
  return os.str();
}

PolyhedronMapCheck check_polyhedron_map(const PolyhedronCompositeMap& f, const Polyhedron& source,
                                        const Polyhedron& target, int per_feature) {
  return check_polyhedron_map(
      f, [&](const Points<3>& y, Points<3>& x, VectorX& residual) { f.inverse(y, x, residual); }, source,
      target, per_feature);
}

PolyhedronMapCheck check_polyhedron_map(const Map<3>& f, const PolyhedronMapInverse& inverse,
                                        const Polyhedron& source, const Polyhedron& target, int per_feature) {
  PolyhedronMapCheck c;
  const Points<3> x0 = polyhedron_check_sample(source, per_feature);
  c.samples = x0.rows();
  Points<3> x;
  Jacobians<3> J;
  f.eval_with_jacobian(x0, x, J);
  const VectorX det = jacobian_determinants<3>(J);
  c.min_det = std::numeric_limits<Real>::infinity();
  for (Index p = 0; p < c.samples; ++p) {
    if (!(det(p) > 0) || !std::isfinite(det(p)) || !x.row(p).allFinite()) ++c.nonpositive;
    if (det(p) < c.min_det) c.min_det = det(p), c.min_det_at = x0.row(p).transpose();
    if (x.row(p).allFinite() && winding_number(target, x.row(p).transpose()) < 0.5) ++c.outside;
  }
  if (c.nonpositive > 0) return c;
  Points<3> back;
  VectorX residual;
  inverse(x, back, residual);
  const Real size = (source.bbox_max() - source.bbox_min()).norm();
  for (Index p = 0; p < c.samples; ++p) {
    const Real e = (back.row(p) - x0.row(p)).norm() / size;
    if (!(e <= kRoundTripTolerance)) ++c.failed_inverse;
    if (!(e <= c.max_round_trip)) c.max_round_trip = e, c.worst_inverse_at = x0.row(p).transpose();
  }
  return c;
}

}  // namespace warpfem::mapping
