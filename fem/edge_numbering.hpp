#pragma once
// Global numbering of the edges of a mesh (each undirected edge once), in the
// order the cells first use them.

#include <cstdint>
#include <memory>
#include <vector>

#include "fem/mesh.hpp"

namespace warpfem::fem {

class EdgeNumbering {
 public:
  template <int dim>
  explicit EdgeNumbering(const Mesh<dim>& mesh);

  Index num_edges() const { return static_cast<Index>(edge_vertices_.size()); }
  /// Edge id of local edge `e` (cell_edges order) of `cell`.
  Index cell_edge(Index cell, int e) const { return cell_edge_(cell, e); }
  /// Edge id of the edge between vertices a and b; -1 if there is none.
  Index find(Index a, Index b) const;
  const std::array<Index, 2>& vertices(Index edge) const {
    return edge_vertices_[static_cast<std::size_t>(edge)];
  }

 private:
  // Edges grouped by their smaller vertex: for vertex a, the edges (a, b > a) are
  // slot_other_[slot_start_[a] .. slot_end_[a]) with ids slot_id_[...], in slots
  // reserved by counting (one per cell edge at a). Built in one pass over the
  // cells, without hashing; ids follow the cells' order (an edge is numbered
  // when a cell first uses it).
  std::vector<std::int32_t> slot_start_, slot_end_;
  std::unique_ptr<std::int32_t[]> slot_other_, slot_id_;
  std::vector<std::array<Index, 2>> edge_vertices_;
  IndexTable cell_edge_;
};

}  // namespace warpfem::fem
