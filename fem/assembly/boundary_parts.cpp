#include "fem/assembly/boundary_parts.hpp"

namespace warpfem::fem {

BoundaryParts::BoundaryParts(const Mesh<2>& mesh, const std::optional<Polygon>& source) : mesh_(&mesh) {
  if (source) locator_.emplace(*source);
}

void BoundaryParts::at(Index facet, const Point<2>& x0, std::vector<int>& parts) const {
  if (locator_)
    locator_->edges_at(x0, parts);
  else
    parts.assign(1, mesh_->facet_tags[static_cast<std::size_t>(facet)]);
}

}  // namespace warpfem::fem
