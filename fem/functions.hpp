#pragma once
// Pointwise data of a problem: functions of the physical point x = f(x0) and time.

#include <functional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace warpfem::fem {

using ScalarFunction = std::function<double(const Point<2>& x, double t)>;
using GradientFunction = std::function<Point<2>(const Point<2>& x, double t)>;

/// A boundary condition on a set of boundary parts: the polygon edges listed
/// (indices of the target polygon's edges; edge i joins vertex i and i + 1).
struct BoundaryCondition {
  std::vector<int> edges;  ///< empty: every boundary edge
  ScalarFunction value;
  bool applies_to(int tag) const;
};

}  // namespace warpfem::fem
