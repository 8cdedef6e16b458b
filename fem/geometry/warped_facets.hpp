#pragma once
// Geometry of warped boundary facets f(F) at the quadrature points of a facet
// rule: x0 on the facet of the simple mesh, x = f(x0), the warped measure
// w |J_f T0| (edges) or w |J_f T0_1 × J_f T0_2| (faces), and the outward unit
// normal of Ω1, all from one batched evaluation of the map at construction.
// Boundary facets of the simple mesh are oriented so that Ω0 lies to their
// left (2D) or behind them (3D); f keeps orientations.

#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/mesh/quadrature.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

template <int dim>
class WarpedFacets {
 public:
  /// The boundary facets `facets` (rows of mesh.boundary_facets) with `rule` on
  /// the reference facet ([0, 1], or the reference triangle / square).
  WarpedFacets(const Mesh<dim>& mesh, std::vector<Index> facets, const QuadratureRule<dim - 1>& rule,
               const mapping::Map<dim>& map);

  Index num_facets() const { return static_cast<Index>(facets_.size()); }
  Index points_per_facet() const { return nq_; }
  Index at(Index i, Index q) const { return i * nq_ + q; }
  /// Row of mesh.boundary_facets of the i-th facet.
  Index facet(Index i) const { return facets_[static_cast<std::size_t>(i)]; }
  const QuadratureRule<dim - 1>& rule() const { return rule_; }

  Point<dim> reference_point(Index p) const { return x0_.row(p).transpose(); }
  Point<dim> point(Index p) const { return x_.row(p).transpose(); }
  Point<dim> normal(Index p) const { return normal_.row(p).transpose(); }
  /// w_q times the warped facet measure at the point.
  double JxW(Index p) const { return JxW_(p); }

 private:
  std::vector<Index> facets_;
  QuadratureRule<dim - 1> rule_;
  Index nq_;
  Points<dim> x0_, x_, normal_;
  VectorX JxW_;
};

}  // namespace warpfem::fem
