#include "fem/assembly/boundary_parts.hpp"

#include "core/error.hpp"

namespace warpfem::fem {

template <int dim>
BoundaryParts<dim>::BoundaryParts(const Mesh<dim>& mesh, const std::optional<Polygon>& source)
    : mesh_(&mesh) {
  if (!source) return;
  require(dim == 2, "boundary parts by point on a source polygon exist in 2D only");
  locator_.emplace(*source);
}

template <int dim>
void BoundaryParts<dim>::at(Index facet, const Point<dim>& x0, std::vector<int>& parts) const {
  if constexpr (dim == 2)
    if (locator_) {
      locator_->edges_at(x0, parts);
      return;
    }
  parts.assign(1, mesh_->facet_tags[static_cast<std::size_t>(facet)]);
}

template class BoundaryParts<2>;
template class BoundaryParts<3>;

}  // namespace warpfem::fem
