#pragma once
// Pointwise data of a problem: functions of the physical point x = f(x0) and time.

#include <functional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace warpfem::fem {

using ScalarFunction = std::function<double(const Point<2>& x, double t)>;
using GradientFunction = std::function<Point<2>(const Point<2>& x, double t)>;

/// A ScalarFunction that is one number everywhere and at all times. Stored in a
/// ScalarFunction it stays recognisable (`f.target<ConstantFunction>()`), so
/// passes over many points (assembly of a source) can skip the per-point call.
struct ConstantFunction {
  double value = 0;
  double operator()(const Point<2>&, double) const { return value; }
};

/// A boundary condition on a set of boundary parts: the polygon edges listed
/// (indices of the target polygon's edges; edge i joins vertex i and i + 1).
struct BoundaryCondition {
  std::vector<int> edges;  ///< empty: every boundary edge
  ScalarFunction value;
};

}  // namespace warpfem::fem
