#pragma once
// Shape functions of a cell element restricted to a boundary facet (its
// trace: the 1D Lagrange functions on an edge, the triangle or square element
// on a face) with the warped facet geometry of WarpedFacets, one facet at a
// time. Local facet DOFs in the order of DofMap::facet_dofs.

#include "fem/geometry/warped_facets.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

template <int dim>
class FacetValues {
 public:
  FacetValues(const LagrangeElement<dim>& cell_element, const WarpedFacets<dim>& facets);

  void reinit(Index i) {
    position_ = i;
    base_ = facets_->at(i, 0);
  }
  /// Index of the current facet in the WarpedFacets' list.
  Index position() const { return position_; }
  /// Its row of mesh.boundary_facets.
  Index facet() const { return facets_->facet(position_); }
  Index num_points() const { return facets_->points_per_facet(); }
  int num_dofs() const { return static_cast<int>(N_.cols()); }

  double JxW(Index q) const { return facets_->JxW(base_ + q); }
  Point<dim> point(Index q) const { return facets_->point(base_ + q); }
  Point<dim> reference_point(Index q) const { return facets_->reference_point(base_ + q); }
  Point<dim> normal(Index q) const { return facets_->normal(base_ + q); }
  double shape_value(Index q, int k) const { return N_(q, k); }

 private:
  const WarpedFacets<dim>* facets_;
  MatrixX N_;  // (points x facet dofs)
  Index position_ = 0, base_ = 0;
};

}  // namespace warpfem::fem
