#include "fem/hierarchy/nested_blocks.hpp"

#include <string>
#include <utility>

#include "core/error.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"

namespace warpfem::fem {

std::vector<char> blocks_sharing_a_vertex(const IndexTable& base_cells, const std::vector<char>& seed) {
  const Index nb = base_cells.rows(), nv = base_cells.cols();
  const Index vertices = nb == 0 ? 0 : Index{base_cells.maxCoeff()} + 1;
  std::vector<char> touched(static_cast<std::size_t>(vertices), 0);
  for (Index b = 0; b < nb; ++b)
    if (seed[static_cast<std::size_t>(b)])
      for (Index k = 0; k < nv; ++k) touched[static_cast<std::size_t>(base_cells(b, k))] = 1;
  std::vector<char> out(static_cast<std::size_t>(nb), 0);
  for (Index b = 0; b < nb; ++b)
    for (Index k = 0; k < nv; ++k)
      if (touched[static_cast<std::size_t>(base_cells(b, k))]) out[static_cast<std::size_t>(b)] = 1;
  return out;
}

std::vector<std::array<Index, 2>> block_cell_ranges(const std::vector<Index>& blocks, Index cells_per_block) {
  std::vector<std::array<Index, 2>> ranges;
  for (Index b : blocks) {
    if (!ranges.empty() && ranges.back()[1] == b * cells_per_block)
      ranges.back()[1] += cells_per_block;
    else
      ranges.push_back({b * cells_per_block, (b + 1) * cells_per_block});
  }
  return ranges;
}

std::vector<Index> NestedBlocks::blocks_near(int rank) const {
  require(base_cells && base_cells->rows() == num_blocks(),
          "NestedBlocks: the base mesh does not match the blocks");
  std::vector<char> own(owner.size(), 0);
  for (std::size_t b = 0; b < owner.size(); ++b) own[b] = owner[b] == rank;
  const std::vector<char> near = blocks_sharing_a_vertex(*base_cells, own);
  std::vector<Index> list;
  for (Index b = 0; b < num_blocks(); ++b)
    if (near[static_cast<std::size_t>(b)]) list.push_back(b);
  return list;
}

template <int dim>
NestedBlocks nested_blocks(const MeshHierarchy<dim>& h, int base, int level, std::vector<int> base_owner) {
  require(base >= 0 && base < level && level < h.num_levels(),
          "nested_blocks: level " + std::to_string(level) + " is not above base level " +
              std::to_string(base) + " in a hierarchy of " + std::to_string(h.num_levels()) + " levels");
  const Mesh<dim>& base_mesh = h.levels[static_cast<std::size_t>(base)];
  require(static_cast<Index>(base_owner.size()) == base_mesh.num_cells(),
          "nested_blocks: " + std::to_string(base_owner.size()) + " owners for " +
              std::to_string(base_mesh.num_cells()) + " base cells");
  NestedBlocks blocks;
  blocks.base_cells = &base_mesh.cells;
  blocks.owner = std::move(base_owner);
  // The blocks' first coarse cells on level - 1 are 2^(dim (k-1)) apart; the
  // refinement into `level` recorded where each coarse cell's new vertices start.
  Index coarse_per_block = 1;
  for (int l = base; l + 1 < level; ++l) coarse_per_block *= RefinedMesh<dim>::children_per_cell;
  blocks.cells_per_block = coarse_per_block * RefinedMesh<dim>::children_per_cell;
  const std::vector<TableIndex>& first_new =
      h.transfers[static_cast<std::size_t>(level - 1)].first_new_vertex;
  const Index nb = blocks.num_blocks();
  require(static_cast<Index>(first_new.size()) == nb * coarse_per_block + 1,
          "nested_blocks: level " + std::to_string(level) +
              " was not refined by refine_uniformly from level " + std::to_string(level - 1));
  blocks.first_vertex.resize(static_cast<std::size_t>(nb) + 1);
  for (Index b = 0; b <= nb; ++b)
    blocks.first_vertex[static_cast<std::size_t>(b)] =
        first_new[static_cast<std::size_t>(b * coarse_per_block)];
  return blocks;
}

template NestedBlocks nested_blocks(const MeshHierarchy<2>&, int, int, std::vector<int>);
template NestedBlocks nested_blocks(const MeshHierarchy<3>&, int, int, std::vector<int>);

RefinedRing refined_ring(const IndexTable& base_cells, const std::vector<int>& base_owner, int rank) {
  const Index nb = base_cells.rows();
  std::vector<char> own(static_cast<std::size_t>(nb), 0);
  for (Index b = 0; b < nb; ++b)
    own[static_cast<std::size_t>(b)] = base_owner[static_cast<std::size_t>(b)] == rank;
  RefinedRing ring;
  ring.near = blocks_sharing_a_vertex(base_cells, own);
  ring.refined = blocks_sharing_a_vertex(base_cells, ring.near);
  for (Index b = 0; b < nb; ++b) {
    if (ring.near[static_cast<std::size_t>(b)]) ring.near_blocks.push_back(b);
    if (ring.refined[static_cast<std::size_t>(b)]) ring.refined_blocks.push_back(b);
  }
  ring.refined_runs = block_cell_ranges(ring.refined_blocks, 1);
  return ring;
}

template <int dim>
void append_partial_level(MeshHierarchy<dim>& h, int base_level, Mesh<dim> fine, const RefinedRing& ring,
                          const std::vector<int>& base_owner, Index cells_per_block,
                          const std::vector<TableIndex>& first_vertex, std::vector<NestedBlocks>& blocks) {
  fine.present_cells = block_cell_ranges(ring.near_blocks, cells_per_block);
  NestedBlocks nested;
  nested.base_cells = &h.levels[static_cast<std::size_t>(base_level)].cells;
  nested.owner = base_owner;
  nested.cells_per_block = cells_per_block;
  nested.first_vertex = first_vertex;
  blocks.push_back(std::move(nested));
  h.transfers.emplace_back();  // the parent layout only (RefinedMesh::parent_of)
  h.levels.push_back(std::move(fine));
}

template void append_partial_level(MeshHierarchy<2>&, int, Mesh<2>, const RefinedRing&,
                                   const std::vector<int>&, Index, const std::vector<TableIndex>&,
                                   std::vector<NestedBlocks>&);
template void append_partial_level(MeshHierarchy<3>&, int, Mesh<3>, const RefinedRing&,
                                   const std::vector<int>&, Index, const std::vector<TableIndex>&,
                                   std::vector<NestedBlocks>&);

std::vector<TableIndex> block_offsets(const std::vector<Index>& count, const std::string& what) {
  std::vector<TableIndex> first(count.size() + 1);
  Index sum = 0;
  for (std::size_t b = 0; b < count.size(); ++b) {
    first[b] = checked_table_size(sum, what);
    sum += count[b];
  }
  first.back() = checked_table_size(sum, what);
  return first;
}

}  // namespace warpfem::fem
