#pragma once
// Pointwise data of an elasticity problem: material, loads and boundary
// conditions as functions of the physical point x = f(x0) (on the warped
// reference configuration f(Ω0)) and time t. Boundary parts are selected by
// polygon edge index (Mesh<2>::facet_tags), e.g. the edges of one gear tooth.

#include <array>
#include <functional>
#include <optional>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/physics/elasticity/material.hpp"
#include "fem/physics/functions.hpp"

namespace warpfem::fem {

using VectorFunction = std::function<Point<2>(const Point<2>& x, double t)>;

/// Prescribed displacement u_c = value[c](x, t) on the listed edges; an empty
/// std::function leaves that component free (e.g. a roller: only u_y = 0).
struct DisplacementCondition {
  std::vector<int> edges;  ///< empty: every boundary edge
  std::array<ScalarFunction<2>, 2> value;
};

/// Dead-load traction (force per unit length of the warped reference boundary f(∂Ω0)).
struct TractionCondition {
  std::vector<int> edges;  ///< empty: every boundary edge
  VectorFunction traction;
};

struct ElasticityData {
  Material material;
  Point<2> gravity = Point<2>::Zero();  ///< acceleration g: body force ρ g per unit reference volume
  VectorFunction body_force;            ///< optional extra body force per unit reference volume
  std::vector<DisplacementCondition> dirichlet;
  std::vector<TractionCondition> neumann;
  /// The source polygon: conditions then select polygon edges per point (see
  /// fem/boundary_parts.hpp); without it, by the facet tags.
  std::optional<Polygon> boundary_polygon;
};

/// The displacement condition that constrains each node of `dofs` (nullptr:
/// free), by the rule of fem/boundary_parts.hpp. Component c of node d is fixed iff
/// result[d] && result[d]->value[c]. Every node of the mesh, on every rank.
std::vector<const DisplacementCondition*> node_conditions(const Mesh<2>& mesh, const DofMap<2>& dofs,
                                                          const ElasticityData& data);

}  // namespace warpfem::fem
