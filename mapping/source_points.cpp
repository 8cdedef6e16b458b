#include "mapping/source_points.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "mapping/harmonic/boundary_data.hpp"

namespace warpfem::mapping {

SourcePointsReport accept_source_points(const Polygon& polygon, Points<2>& x, const std::string& file) {
  constexpr std::size_t kListed = 10;
  const Real tolerance = kBoundaryTolerance * diameter(polygon);
  SourcePointsReport report;
  std::vector<std::pair<Index, Real>> outside;
  Index count = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    const Point<2> q = x.row(p).transpose();
    if (!q.allFinite()) {
      ++count;
      if (outside.size() < kListed) outside.emplace_back(p, std::numeric_limits<Real>::quiet_NaN());
      continue;
    }
    if (polygon.side_of(q) >= 0) continue;
    Real distance = 0;
    const BoundaryPoint at = closest_boundary_point(polygon, q, &distance);
    if (distance <= tolerance) {
      x.row(p) = boundary_position(polygon, at).transpose();
      ++report.snapped;
      continue;
    }
    ++count;
    if (outside.size() < kListed) outside.emplace_back(p, distance);
  }
  if (outside.empty()) return report;
  std::ostringstream what;
  what << std::setprecision(10);
  for (std::size_t k = 0; k < outside.size(); ++k) {
    const auto [p, distance] = outside[k];
    what << (k ? "; " : "") << "point " << p + 1 << " (" << x(p, 0) << ", " << x(p, 1) << ") ";
    if (std::isnan(distance))
      what << "is not a finite number";
    else
      what << "lies outside the source polygon by " << std::setprecision(3) << distance
           << std::setprecision(10);
  }
  if (count > static_cast<Index>(outside.size()))
    what << " (" << count << " of " << x.rows() << " points are outside; the first " << outside.size()
         << " are listed)";
  std::ostringstream hint;
  hint << "the map is defined on the source polygon only; points up to " << std::setprecision(3) << tolerance
       << " (1e-12 of its diameter) outside count as boundary points";
  throw Error(what.str(), {.file = file, .key_path = "", .hint = hint.str()});
}

}  // namespace warpfem::mapping
