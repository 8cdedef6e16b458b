#include "multigrid/dirichlet_dofs.hpp"

#include <optional>

#include "fem/boundary_locator.hpp"

namespace warpfem::multigrid {

std::vector<char> dirichlet_dofs(const fem::Mesh<2>& mesh, const fem::DofMap& dofs,
                                 const fem::PoissonData& data) {
  std::vector<char> mask(static_cast<std::size_t>(dofs.num_dofs()), 0);
  if (data.dirichlet.empty()) return mask;
  std::optional<fem::BoundaryLocator> locator;
  if (data.boundary_polygon) locator.emplace(*data.boundary_polygon);
  std::vector<int> edges;
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f) {
    if (!mesh.has_facet(f)) continue;  // outside a partial level's stored cells
    for (Index d : dofs.facet_dofs(mesh, f)) {
      char& m = mask[static_cast<std::size_t>(d)];
      if (m) continue;
      if (locator)
        locator->edges_at(dofs.dof_points().row(d).transpose(), edges);
      else
        edges.assign(1, mesh.facet_tags[static_cast<std::size_t>(f)]);
      for (const auto& bc : data.dirichlet)
        for (int e : edges) m = m || bc.applies_to(e);
    }
  }
  return mask;
}

}  // namespace warpfem::multigrid
