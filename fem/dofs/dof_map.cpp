#include "fem/dofs/dof_map.hpp"

#include "core/error.hpp"

namespace warpfem::fem {

DofMap::DofMap(const Mesh<2>& mesh, const LagrangeElement<2>& element) : element_(element) {
  require(mesh.cell_type == element.cell_type(),
          "DofMap: element " + element.name() + " does not match " + to_string(mesh.cell_type) + " cells");
  const int per_edge = element.dofs_per_edge(), interior = element.interior_dofs();
  if (per_edge > 0) edges_.emplace(mesh);
  const Index nv = mesh.num_vertices(), ne = edges_ ? edges_->num_edges() : 0, nc = mesh.num_cells();
  num_dofs_ = checked_table_size(nv + ne * per_edge + nc * interior, "DofMap: DOFs of " + element.name());
  const int nloc = element.num_dofs();
  const int nvert = element.num_vertex_dofs();
  const auto& edges = cell_edges(mesh.cell_type);
  if (per_edge == 0 && interior == 0 && nloc == nvert && mesh.cells.cols() == nvert) {
    vertex_dofs_ = &mesh;  // P1/Q1: the DOFs are the vertices, numbered as the mesh numbers them
    return;
  }
  cell_dofs_.resize(nc, nloc);
  for (Index c = 0; c < nc; ++c) {
    for (int k = 0; k < nvert; ++k) cell_dofs_(c, k) = mesh.cells(c, k);
    for (int e = 0; e < static_cast<int>(edges.size()) && per_edge > 0; ++e)
      cell_dofs_(c, nvert + e) = nv + edges_->cell_edge(c, e);
    for (int k = 0; k < interior; ++k)
      cell_dofs_(c, nloc - interior + k) = nv + ne * per_edge + c * interior + k;
  }
  // Node positions: map the reference nodes through the straight cell geometry.
  const LagrangeElement<2> geo(mesh.cell_type, 1);
  const MatrixX N = geo.values(element.nodes());
  dof_points_.resize(num_dofs_, 2);
  for (Index c = 0; c < nc; ++c)
    for (int k = 0; k < nloc; ++k) {
      Point<2> x = Point<2>::Zero();
      for (int v = 0; v < nvert; ++v) x += N(k, v) * mesh.vertex(mesh.cells(c, v));
      dof_points_.row(cell_dofs_(c, k)) = x.transpose();
    }
}

std::vector<Index> DofMap::facet_dofs(const Mesh<2>& mesh, Index facet) const {
  const Index a = mesh.boundary_facets(facet, 0), b = mesh.boundary_facets(facet, 1);
  std::vector<Index> out{a, b};
  if (edges_) {
    const Index e = edges_->find(a, b);
    require(e >= 0, "DofMap: boundary facet is not a mesh edge");
    out.push_back(mesh.num_vertices() + e);
  }
  return out;
}

}  // namespace warpfem::fem
