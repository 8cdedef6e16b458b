#pragma once
// Helpers shared by the harmonic-map tests.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "mapping/map.hpp"
#include "mapping/map_spec.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping::test {

/// Points of `x` at least `margin` inside polygon (distance to every edge).
inline Points<2> keep_away_from_boundary(const Points<2>& x, const Polygon& P, Real margin) {
  std::vector<Index> keep;
  for (Index p = 0; p < x.rows(); ++p) {
    Real d = 1e300;
    for (Index i = 0; i < P.size(); ++i) {
      const Point<2> a = P.vertex(i), e = P.vertex(i + 1) - a, q = x.row(p).transpose();
      const Real t = std::clamp((q - a).dot(e) / e.squaredNorm(), Real{0}, Real{1});
      d = std::min(d, (a + t * e - q).norm());
    }
    if (d >= margin) keep.push_back(p);
  }
  Points<2> out(static_cast<Index>(keep.size()), 2);
  for (std::size_t k = 0; k < keep.size(); ++k) out.row(static_cast<Index>(k)) = x.row(keep[k]);
  return out;
}

/// Reads examples/maps/<name>.json (composite harmonic keys included) as the application does.
inline MapSpec load_harmonic_example(const std::string& name) {
  return load_example(name);
}

}  // namespace warpfem::mapping::test
