#include "fem/values/facet_values.hpp"

#include "core/error.hpp"

namespace warpfem::fem {

template <int dim>
FacetValues<dim>::FacetValues(const LagrangeElement<dim>& cell_element, const WarpedFacets<dim>& facets)
    : facets_(&facets) {
  const int order = cell_element.order();
  const auto& rule = facets.rule();
  if constexpr (dim == 2) {
    N_.resize(rule.size(), order + 1);
    double phi[3];
    for (Index q = 0; q < rule.size(); ++q) {
      edge_shape_functions(order, rule.points(q, 0), phi);
      for (int k = 0; k <= order; ++k) N_(q, k) = phi[k];
    }
  } else {
    const CellType face =
        cell_element.cell_type() == CellType::tetrahedron ? CellType::triangle : CellType::quadrilateral;
    N_ = LagrangeElement<2>(face, order).values(rule.points);
  }
}

template class FacetValues<2>;
template class FacetValues<3>;

}  // namespace warpfem::fem
