#include "fem/edge_numbering.hpp"

namespace warpfem::fem {

template <int dim>
EdgeNumbering::EdgeNumbering(const Mesh<dim>& mesh) {
  const auto& edges = cell_edges(mesh.cell_type);
  const Index nc = mesh.num_cells(), nv = mesh.num_vertices(), ne = static_cast<Index>(edges.size());
  cell_edge_.resize(nc, ne);
  // 1. Bucket every cell edge by its smaller vertex.
  std::vector<Index> count(static_cast<std::size_t>(nv) + 1, 0);
  for (Index c = 0; c < nc; ++c)
    for (Index e = 0; e < ne; ++e)
      ++count[std::min(mesh.cells(c, edges[e][0]), mesh.cells(c, edges[e][1])) + 1];
  for (Index v = 0; v < nv; ++v) count[v + 1] += count[v];
  std::vector<Index> slot(count.begin(), count.end() - 1);
  std::vector<Index> bucket_other(static_cast<std::size_t>(count[nv])), bucket_ref(bucket_other.size());
  for (Index c = 0; c < nc; ++c)
    for (Index e = 0; e < ne; ++e) {
      const Index a = mesh.cells(c, edges[e][0]), b = mesh.cells(c, edges[e][1]);
      const Index k = slot[std::min(a, b)]++;
      bucket_other[k] = std::max(a, b);
      bucket_ref[k] = c * ne + e;
    }
  // 2. Deduplicate inside each (small) bucket and number the edges.
  start_.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (Index a = 0; a < nv; ++a) {
    start_[a] = static_cast<Index>(other_.size());
    for (Index k = count[a]; k < count[a + 1]; ++k) {
      const Index b = bucket_other[k];
      Index id = -1;
      for (Index m = start_[a]; m < static_cast<Index>(other_.size()); ++m)
        if (other_[m] == b) id = id_[m];
      if (id < 0) {
        id = static_cast<Index>(edge_vertices_.size());
        edge_vertices_.push_back({a, b});
        other_.push_back(b);
        id_.push_back(id);
      }
      cell_edge_(bucket_ref[k] / ne, bucket_ref[k] % ne) = id;
    }
  }
  start_[nv] = static_cast<Index>(other_.size());
}

Index EdgeNumbering::find(Index a, Index b) const {
  if (a > b) std::swap(a, b);
  if (a < 0 || a + 1 >= static_cast<Index>(start_.size())) return -1;
  for (Index m = start_[a]; m < start_[a + 1]; ++m)
    if (other_[m] == b) return id_[m];
  return -1;
}

template EdgeNumbering::EdgeNumbering(const Mesh<2>&);
template EdgeNumbering::EdgeNumbering(const Mesh<3>&);

}  // namespace warpfem::fem
