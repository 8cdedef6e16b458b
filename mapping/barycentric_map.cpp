#include "mapping/barycentric_map.hpp"

#include <limits>

#include "mapping/distortion.hpp"

namespace warpfem::mapping {

BarycentricMap::BarycentricMap(const Polygon& source, const Polygon& target, Coordinates coordinates)
    : step_(source, target.vertices(), coordinates),
      source_name_(source.name()),
      target_name_(target.name()) {}

void BarycentricMap::jacobian(const Points<2>& x0, Jacobians<2>& J) const {
  Points<2> x;
  step_.apply(x0, x, &J);
}

std::string BarycentricMap::describe() const {
  return to_string(step_.coordinates()) + " barycentric map " + source_name_ + " -> " + target_name_ + " (" +
         std::to_string(step_.source().size()) + " vertices)";
}

Real min_det_jacobian(const Map<2>& map, const Points<2>& samples) {
  if (samples.rows() == 0) return std::numeric_limits<Real>::infinity();
  Jacobians<2> J;
  map.jacobian(samples, J);
  const VectorX det = jacobian_determinants<2>(J);
  return min_entry(det.data(), det.size());
}

}  // namespace warpfem::mapping
