#pragma once
// Pointwise data of a problem: functions of the physical point x = f(x0) and time.

#include <functional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace warpfem::fem {

template <int dim>
using ScalarFunction = std::function<double(const Point<dim>& x, double t)>;
template <int dim>
using GradientFunction = std::function<Point<dim>(const Point<dim>& x, double t)>;

/// A ScalarFunction that is one number everywhere and at all times. Stored in a
/// ScalarFunction it stays recognisable (`f.target<ConstantFunction>()`), so
/// passes over many points (assembly of a source) can skip the per-point call.
struct ConstantFunction {
  double value = 0;
  template <class AnyPoint>
  double operator()(const AnyPoint&, double) const {
    return value;
  }
};

/// A boundary condition on a set of boundary parts: in 2D the polygon edges
/// listed (edge i joins vertex i and i + 1), in 3D the facet tags listed
/// (Mesh::facet_tags: polyhedron face groups, box faces).
template <int dim>
struct BoundaryCondition {
  std::vector<int> edges;  ///< the parts; empty: every part
  ScalarFunction<dim> value;
};

}  // namespace warpfem::fem
