#include "core/mesh/boundary_locator.hpp"

#include <algorithm>
#include <limits>

namespace warpfem {
namespace {
double distance_to_segment(const Point<2>& p, const Point<2>& a, const Point<2>& b) {
  const Point<2> d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}
}  // namespace

BoundaryLocator::BoundaryLocator(const Polygon& source, double relative_tolerance)
    : polygon_(source), tolerance_(relative_tolerance * (source.bbox_max() - source.bbox_min()).norm()) {}

void BoundaryLocator::edges_at(const Point<2>& x0, std::vector<int>& edges) const {
  edges.clear();
  for (Index e = 0; e < polygon_.size(); ++e)
    if (distance_to_segment(x0, polygon_.vertex(e), polygon_.vertex(e + 1)) <= tolerance_)
      edges.push_back(static_cast<int>(e));
}

int BoundaryLocator::edge_at(const Point<2>& x0) const {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (Index e = 0; e < polygon_.size(); ++e) {
    const double d = distance_to_segment(x0, polygon_.vertex(e), polygon_.vertex(e + 1));
    if (d < best_d) best_d = d, best = static_cast<int>(e);
  }
  return best_d <= tolerance_ ? best : -1;
}

}  // namespace warpfem
