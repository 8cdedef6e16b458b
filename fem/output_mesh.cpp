#include "fem/output_mesh.hpp"

#include <algorithm>
#include <functional>
#include <string>
#include <unordered_map>

#include "core/error.hpp"
#include "fem/lagrange_element.hpp"
#include "fem/warped_geometry.hpp"

namespace warpfem::fem {

OutputMesh make_output_mesh(const Mesh<2>& mesh, const DofDistribution& dist, const mapping::Map<2>& map,
                            int order) {
  OutputMesh out;
  out.cell_type = mesh.cell_type;
  out.order = order;
  const LagrangeElement<2> element(mesh.cell_type, order);
  require(element.dofs_per_edge() <= 1, "make_output_mesh: output order " + std::to_string(order) +
                                            " is not supported (at most one node per edge)");
  const int nloc = element.num_dofs(), nvert = element.num_vertex_dofs();
  const int edge_nodes_end =
      nvert + static_cast<int>(cell_edges(mesh.cell_type).size()) * element.dofs_per_edge();
  const auto& edges = cell_edges(mesh.cell_type);
  // Node positions in Ω0: the straight cell geometry at the element's nodes.
  const MatrixX geometry = LagrangeElement<2>(mesh.cell_type, 1).values(element.nodes());  // nodes x vertices
  const auto& cells = dist.local_cells();
  out.cells.resize(static_cast<Index>(cells.size()), nloc);
  out.cell_ids = cells;
  // Nodes the local cells share: vertices by their number, edge nodes by their
  // edge's two vertex numbers (no mesh-wide numbering of edges, so the output
  // of a level stored only around this rank's cells works too); interior nodes
  // belong to one cell.
  struct Key {
    Index a, b;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return std::hash<Index>()(k.a) ^ (std::hash<Index>()(k.b) * 0x9E3779B97F4A7C15ULL);
    }
  };
  std::unordered_map<Key, Index, KeyHash> index;
  index.reserve(cells.size() * static_cast<std::size_t>(nloc) / 2 + 1);
  std::vector<Point<2>> positions;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Index c = cells[i];
    for (int k = 0; k < nloc; ++k) {
      Index node = -1;
      if (k < edge_nodes_end) {
        Key key{mesh.cells(c, k), -1};
        if (k >= nvert) {
          const auto& e = edges[static_cast<std::size_t>(k - nvert)];
          const Index p = mesh.cells(c, e[0]), q = mesh.cells(c, e[1]);
          key = {std::min(p, q), std::max(p, q)};
        }
        const auto [it, inserted] = index.try_emplace(key, static_cast<Index>(positions.size()));
        node = it->second;
        if (!inserted) {
          out.cells(static_cast<Index>(i), k) = node;
          continue;
        }
      }
      if (node < 0) node = static_cast<Index>(positions.size());
      Point<2> x = Point<2>::Zero();
      for (int v = 0; v < nvert; ++v) x += geometry(k, v) * mesh.vertex(mesh.cells(c, v));
      positions.push_back(x);
      out.node_source_.emplace_back(static_cast<Index>(i), k);
      out.cells(static_cast<Index>(i), k) = node;
    }
  }
  const Index n = static_cast<Index>(positions.size());
  out.reference_points.resize(n, 2);
  for (Index i = 0; i < n; ++i)
    out.reference_points.row(i) = positions[static_cast<std::size_t>(i)].transpose();
  out.points = warp_nodes(map, out.reference_points, &out.map_det);
  return out;
}

VectorX OutputMesh::interpolate(const DofMap& dofs, const DofDistribution& dist,
                                const VectorX& relevant_values) const {
  const LagrangeElement<2> out_element(cell_type, order);
  const MatrixX phi = dofs.element().values(out_element.nodes());  // output nodes x element dofs
  VectorX values(static_cast<Index>(node_source_.size()));
  for (std::size_t i = 0; i < node_source_.size(); ++i) {
    const auto [cell_index, k] = node_source_[i];
    const Index c = cell_ids[static_cast<std::size_t>(cell_index)];
    double v = 0;
    for (Index j = 0; j < phi.cols(); ++j)
      v += phi(k, j) * relevant_values(dist.relevant_index(dofs.cell_dofs()(c, j)));
    values(static_cast<Index>(i)) = v;
  }
  return values;
}

}  // namespace warpfem::fem
