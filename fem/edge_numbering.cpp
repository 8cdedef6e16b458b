#include "fem/edge_numbering.hpp"

namespace warpfem::fem {

template <int dim>
EdgeNumbering::EdgeNumbering(const Mesh<dim>& mesh) {
  const auto& edges = cell_edges(mesh.cell_type);
  cell_edge_.resize(mesh.num_cells(), static_cast<Index>(edges.size()));
  ids_.reserve(static_cast<std::size_t>(mesh.num_cells() * 2));
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const Index a = mesh.cells(c, edges[e][0]), b = mesh.cells(c, edges[e][1]);
      auto [it, inserted] = ids_.try_emplace(key(a, b), num_edges());
      if (inserted) edge_vertices_.push_back({std::min(a, b), std::max(a, b)});
      cell_edge_(c, static_cast<Index>(e)) = it->second;
    }
  }
}

Index EdgeNumbering::find(Index a, Index b) const {
  auto it = ids_.find(key(a, b));
  return it == ids_.end() ? -1 : it->second;
}

template EdgeNumbering::EdgeNumbering(const Mesh<2>&);
template EdgeNumbering::EdgeNumbering(const Mesh<3>&);

}  // namespace warpfem::fem
