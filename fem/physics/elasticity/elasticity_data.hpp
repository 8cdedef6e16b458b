#pragma once
// Pointwise data of an elasticity problem: material, loads and boundary
// conditions as functions of the physical point x = f(x0) (on the warped
// reference configuration f(Ω0)) and time t. Boundary parts are selected by
// part id (fem/assembly/boundary_parts.hpp): polygon edges in 2D (e.g. the
// edges of one gear tooth), tagged face groups in 3D.

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

template <int dim>
using ComponentFunction = std::function<double(const Point<dim>& x, double t)>;
template <int dim>
using VectorFunction = std::function<Point<dim>(const Point<dim>& x, double t)>;

/// Prescribed displacement u_c = value[c](x, t) on the listed parts; an empty
/// std::function leaves that component free (e.g. a roller: only u_y = 0).
template <int dim>
struct DisplacementCondition {
  std::vector<int> edges;  ///< boundary parts; empty: every part
  std::array<ComponentFunction<dim>, dim> value;
};

/// Dead-load traction (force per unit measure of the warped reference boundary f(∂Ω0)).
template <int dim>
struct TractionCondition {
  std::vector<int> edges;  ///< boundary parts; empty: every part
  VectorFunction<dim> traction;
};

template <int dim>
struct ElasticityData {
  Material material;
  Point<dim> gravity = Point<dim>::Zero();  ///< acceleration g: body force ρ g per unit reference volume
  VectorFunction<dim> body_force;           ///< optional extra body force per unit reference volume
  std::vector<DisplacementCondition<dim>> dirichlet;
  std::vector<TractionCondition<dim>> neumann;
  /// 2D only: the source polygon; conditions then select polygon edges per point (see
  /// fem/assembly/boundary_parts.hpp); without it, by the facet tags.
  std::optional<Polygon> boundary_polygon;
};

/// The displacement condition that constrains each node of `dofs` (nullptr:
/// free), by the rule of fem/assembly/boundary_parts.hpp. Component c of node d is fixed iff
/// result[d] && result[d]->value[c]. Every node of the mesh, on every rank.
template <int dim>
std::vector<const DisplacementCondition<dim>*> node_conditions(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                                               const ElasticityData<dim>& data);

}  // namespace warpfem::fem
