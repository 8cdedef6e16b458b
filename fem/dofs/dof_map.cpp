#include "fem/dofs/dof_map.hpp"

#include <string>

#include "core/error.hpp"

namespace warpfem::fem {

template <int dim>
DofMap<dim>::DofMap(const Mesh<dim>& mesh, const LagrangeElement<dim>& element) : element_(element) {
  require(mesh.cell_type == element.cell_type(),
          "DofMap: element " + element.name() + " does not match " + to_string(mesh.cell_type) + " cells");
  const int per_edge = element.dofs_per_edge(), per_face = element.dofs_per_face();
  const int interior = element.interior_dofs();
  require(per_edge <= 1 && per_face <= 1,
          "DofMap: element " + element.name() + " has more than one node per edge or face (orders ≤ 2 only)");
  if (per_edge > 0) edges_.emplace(mesh);
  if constexpr (dim == 3)
    if (per_face > 0) faces_.emplace(mesh);
  const Index nv = mesh.num_vertices(), ne = num_edges(), nf = num_faces(), nc = mesh.num_cells();
  num_dofs_ = checked_table_size(nv + ne * per_edge + nf * per_face + nc * interior,
                                 "DofMap: DOFs of " + element.name());
  const int nloc = element.num_dofs();
  const int nvert = element.num_vertex_dofs();
  if (per_edge == 0 && interior == 0 && nloc == nvert && mesh.cells.cols() == nvert) {
    vertex_dofs_ = &mesh;  // P1/Q1: the DOFs are the vertices, numbered as the mesh numbers them
    return;
  }
  const int cell_edge_count = static_cast<int>(cell_edges(mesh.cell_type).size());
  const int cell_face_count = per_face > 0 ? static_cast<int>(cell_faces(mesh.cell_type).size()) : 0;
  const int first_face_node = nvert + cell_edge_count * per_edge;
  cell_dofs_.resize(nc, nloc);
  for (Index c = 0; c < nc; ++c) {
    for (int k = 0; k < nvert; ++k) cell_dofs_(c, k) = mesh.cells(c, k);
    for (int e = 0; e < cell_edge_count && per_edge > 0; ++e)
      cell_dofs_(c, nvert + e) = static_cast<TableIndex>(nv + edges_->cell_edge(c, e));
    for (int f = 0; f < cell_face_count; ++f)
      cell_dofs_(c, first_face_node + f) = static_cast<TableIndex>(nv + ne + faces_->cell_face(c, f));
    for (int k = 0; k < interior; ++k)
      cell_dofs_(c, nloc - interior + k) = static_cast<TableIndex>(nv + ne + nf + c * interior + k);
  }
  // Node positions: map the reference nodes through the straight cell geometry.
  const LagrangeElement<dim> geo(mesh.cell_type, 1);
  const MatrixX N = geo.values(element.nodes());
  dof_points_.resize(num_dofs_, dim);
  for (Index c = 0; c < nc; ++c)
    for (int k = 0; k < nloc; ++k) {
      Point<dim> x = Point<dim>::Zero();
      for (int v = 0; v < nvert; ++v) x += N(k, v) * mesh.vertex(mesh.cells(c, v));
      dof_points_.row(cell_dofs_(c, k)) = x.transpose();
    }
}

template <int dim>
std::vector<Index> DofMap<dim>::facet_dofs(const Mesh<dim>& mesh, Index facet) const {
  if constexpr (dim == 2) {
    const Index a = mesh.boundary_facets(facet, 0), b = mesh.boundary_facets(facet, 1);
    std::vector<Index> out{a, b};
    if (edges_) {
      const Index e = edges_->find(a, b);
      require(e >= 0, "DofMap: boundary facet is not a mesh edge");
      out.push_back(mesh.num_vertices() + e);
    }
    return out;
  } else {
    const TableIndex* v = &mesh.boundary_facets(facet, 0);
    const int count = static_cast<int>(mesh.boundary_facets.cols());
    std::vector<Index> out(v, v + count);
    if (edges_)
      for (const auto& e : cell_edges(facet_type(mesh.cell_type))) {
        const Index id = edges_->find(v[e[0]], v[e[1]]);
        require(id >= 0,
                "DofMap: an edge of boundary facet " + std::to_string(facet) + " is not a mesh edge");
        out.push_back(mesh.num_vertices() + id);
      }
    if (faces_) {
      const Index id = faces_->find(v, count);
      require(id >= 0, "DofMap: boundary facet " + std::to_string(facet) + " is not a face of a cell");
      out.push_back(mesh.num_vertices() + num_edges() + id);
    }
    return out;
  }
}

template class DofMap<2>;
template class DofMap<3>;

}  // namespace warpfem::fem
