#pragma once
// Global numbering of the edges of a mesh (each undirected edge once), in the
// order the cells first use them.

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "core/mesh/mesh.hpp"

namespace warpfem {

class EdgeNumbering {
 public:
  template <int dim>
  explicit EdgeNumbering(const Mesh<dim>& mesh);
  /// A numbering whose tables were derived elsewhere (refine_uniformly numbers
  /// the fine mesh's edges from the coarse ones, the same ids the constructor
  /// above would give): the id of local edge e of cell c, each edge's vertices
  /// (smaller first), and optionally the edge of every boundary facet. find()
  /// builds its lookup table on first use.
  EdgeNumbering(IndexTable cell_edge, std::vector<std::array<Index, 2>> edge_vertices,
                std::vector<TableIndex> boundary_facet_edge = {});
  EdgeNumbering(EdgeNumbering&&) = default;
  EdgeNumbering& operator=(EdgeNumbering&&) = default;

  Index num_edges() const { return static_cast<Index>(edge_vertices_.size()); }
  Index num_cells() const { return cell_edge_.rows(); }
  /// Edge id of local edge `e` (cell_edges order) of `cell`.
  Index cell_edge(Index cell, int e) const { return cell_edge_(cell, e); }
  /// Edge id of the edge between vertices a and b; -1 if there is none.
  Index find(Index a, Index b) const;
  /// Edge id of boundary facet f of the mesh (f's vertices a, b): from the
  /// derived table if there is one, else find(a, b).
  Index boundary_facet_edge(Index f, Index a, Index b) const {
    return boundary_facet_edge_.empty() ? find(a, b) : boundary_facet_edge_[static_cast<std::size_t>(f)];
  }
  const std::array<Index, 2>& vertices(Index edge) const {
    return edge_vertices_[static_cast<std::size_t>(edge)];
  }

 private:
  // Edges grouped by their smaller vertex: for vertex a, the edges (a, b > a) are
  // slot_other_[slot_start_[a] .. slot_end_[a]) with ids slot_id_[...], in slots
  // reserved by counting (one per cell edge at a). Built in one pass over the
  // cells, without hashing; ids follow the cells' order (an edge is numbered
  // when a cell first uses it).
  // A derived numbering builds them on the first find() (from edge_vertices_).
  void build_slots_from_edges() const;
  mutable std::unique_ptr<std::once_flag> slots_built_ = std::make_unique<std::once_flag>();
  mutable std::vector<std::int32_t> slot_start_, slot_end_;
  mutable std::unique_ptr<std::int32_t[]> slot_other_, slot_id_;
  std::vector<std::array<Index, 2>> edge_vertices_;
  IndexTable cell_edge_;
  std::vector<TableIndex> boundary_facet_edge_;
  bool derived_ = false;
};

}  // namespace warpfem
