#include "multigrid/dirichlet_dofs.hpp"

#include "fem/assembly/boundary_parts.hpp"

namespace warpfem::multigrid {

std::vector<char> dirichlet_dofs(const warpfem::Mesh<2>& mesh, const fem::DofMap<2>& dofs,
                                 const fem::PoissonData& data) {
  const fem::BoundaryParts parts(mesh, data.boundary_polygon);
  const std::vector<int> selected = fem::boundary_dof_conditions(mesh, dofs, parts, data.dirichlet);
  std::vector<char> mask(selected.size(), 0);
  for (std::size_t d = 0; d < selected.size(); ++d) mask[d] = selected[d] >= 0;
  return mask;
}

}  // namespace warpfem::multigrid
