#include "core/mesh/edge_numbering.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>

#include "core/error.hpp"
#include "core/prefault.hpp"

namespace warpfem {

template <int dim>
EdgeNumbering::EdgeNumbering(const Mesh<dim>& mesh) {
  mesh.require_whole("EdgeNumbering");
  const auto& edges = cell_edges(mesh.cell_type);
  const Index nc = mesh.num_cells(), nv = mesh.num_vertices(), ne = static_cast<Index>(edges.size());
  // 32-bit slots (half the memory, which is mostly first-touch cost): vertex and
  // edge numbers of a mesh PETSc can number fit (PetscInt is 32-bit).
  require(nv < std::numeric_limits<std::int32_t>::max() && nc * ne < std::numeric_limits<std::int32_t>::max(),
          "EdgeNumbering: more than 2^31 vertices or cell edges");
  cell_edge_.resize(nc, ne);
  prefault(cell_edge_.data(), static_cast<std::size_t>(cell_edge_.size()) * sizeof(cell_edge_(0, 0)));
  // 1. Every cell edge (a, b), a < b, reserves a slot with its smaller vertex a:
  // an upper bound on the number of distinct edges (a, ·).
  slot_start_.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (Index c = 0; c < nc; ++c)
    for (Index e = 0; e < ne; ++e)
      ++slot_start_[std::min(mesh.cells(c, edges[e][0]), mesh.cells(c, edges[e][1])) + 1];
  for (Index v = 0; v < nv; ++v) slot_start_[v + 1] += slot_start_[v];
  // 2. One pass over the cells in order: an edge is numbered when a cell first
  // uses it, so edge ids (and the P2 DOFs nv + e) follow the cells' order. The
  // used slots stay as find()'s table (unused ones are never touched).
  const std::size_t slots = static_cast<std::size_t>(slot_start_[nv]);
  slot_other_ = std::make_unique_for_overwrite<std::int32_t[]>(slots);
  slot_id_ = std::make_unique_for_overwrite<std::int32_t[]>(slots);
  prefault(slot_other_.get(), slots * sizeof(std::int32_t));
  prefault(slot_id_.get(), slots * sizeof(std::int32_t));
  slot_end_.assign(slot_start_.begin(), slot_start_.end() - 1);
  edge_vertices_.reserve(slots);  // untouched capacity costs no memory traffic
  for (Index c = 0; c < nc; ++c)
    for (Index e = 0; e < ne; ++e) {
      Index a = mesh.cells(c, edges[e][0]), b = mesh.cells(c, edges[e][1]);
      if (a > b) std::swap(a, b);
      Index id = -1;
      for (Index m = slot_start_[a]; m < slot_end_[a]; ++m)
        if (slot_other_[m] == b) {
          id = slot_id_[m];
          break;
        }
      if (id < 0) {
        id = static_cast<Index>(edge_vertices_.size());
        edge_vertices_.push_back({a, b});
        slot_other_[slot_end_[a]] = static_cast<std::int32_t>(b);
        slot_id_[slot_end_[a]++] = static_cast<std::int32_t>(id);
      }
      cell_edge_(c, e) = id;
    }
}

EdgeNumbering::EdgeNumbering(IndexTable cell_edge, std::vector<std::array<Index, 2>> edge_vertices,
                             std::vector<TableIndex> boundary_facet_edge)
    : edge_vertices_(std::move(edge_vertices)),
      cell_edge_(std::move(cell_edge)),
      boundary_facet_edge_(std::move(boundary_facet_edge)),
      derived_(true) {
  require(static_cast<Index>(edge_vertices_.size()) < std::numeric_limits<std::int32_t>::max(),
          "EdgeNumbering: more than 2^31 edges");
}

void EdgeNumbering::build_slots_from_edges() const {
  // Edges grouped by their smaller vertex, in id order (one counting pass).
  Index nv = 0;
  for (const auto& ev : edge_vertices_) nv = std::max(nv, ev[1] + 1);
  slot_start_.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (const auto& ev : edge_vertices_) ++slot_start_[ev[0] + 1];
  for (Index v = 0; v < nv; ++v) slot_start_[v + 1] += slot_start_[v];
  slot_end_.assign(slot_start_.begin(), slot_start_.end() - 1);
  slot_other_ = std::make_unique_for_overwrite<std::int32_t[]>(edge_vertices_.size());
  slot_id_ = std::make_unique_for_overwrite<std::int32_t[]>(edge_vertices_.size());
  for (std::size_t e = 0; e < edge_vertices_.size(); ++e) {
    const Index a = edge_vertices_[e][0];
    slot_other_[slot_end_[a]] = static_cast<std::int32_t>(edge_vertices_[e][1]);
    slot_id_[slot_end_[a]++] = static_cast<std::int32_t>(e);
  }
}

Index EdgeNumbering::find(Index a, Index b) const {
  if (derived_) std::call_once(*slots_built_, [this] { build_slots_from_edges(); });
  if (a > b) std::swap(a, b);
  if (a < 0 || a >= static_cast<Index>(slot_end_.size())) return -1;
  for (Index m = slot_start_[a]; m < slot_end_[a]; ++m)
    if (slot_other_[m] == b) return slot_id_[m];
  return -1;
}

template EdgeNumbering::EdgeNumbering(const Mesh<2>&);
template EdgeNumbering::EdgeNumbering(const Mesh<3>&);

}  // namespace warpfem
