#include "fem/hierarchy/mesh_hierarchy.hpp"

#include <optional>

#include "core/error.hpp"
#include "core/log.hpp"
#include "fem/dofs/cell_partition.hpp"
#include "fem/hierarchy/partial_refinement.hpp"

namespace warpfem::fem {

template <int dim>
MeshHierarchy<dim>::MeshHierarchy(Mesh<dim> coarse, int refinements) {
  levels.push_back(std::move(coarse));
  refine_whole(refinements, refinements);
}

template <int dim>
std::optional<EdgeNumbering> MeshHierarchy<dim>::refine_whole(int count, int total) {
  // Each refinement numbers the next level's edges from its own (no search),
  // except for a level nobody refines (the total-th).
  std::optional<EdgeNumbering> edges;
  for (int r = 0; r < count; ++r) {
    transfers.push_back(refine_uniformly(levels.back(), edges ? &*edges : nullptr, r + 1 < total));
    edges = std::move(transfers.back().fine_edges);
    transfers.back().fine_edges.reset();
    levels.push_back(std::move(transfers.back().mesh));  // the parent maps stay in `transfers`
  }
  return edges;
}

namespace {
/// The level nested_partitions() cuts along the Morton curve last (every
/// coarser level is cut too, every finer one inherits): the coarsest with at
/// least `min_cells_per_part` cells per part, else the finest.
/// Owners of a level cut along its Morton curve (all rank 0's for one part).
template <int dim>
std::vector<int> cut_level(const Mesh<dim>& mesh, int num_parts) {
  return num_parts == 1 ? std::vector<int>(static_cast<std::size_t>(mesh.num_cells()), 0)
                        : partition_cells(mesh, num_parts);
}

template <int dim>
int partition_base_level(const MeshHierarchy<dim>& h, int num_parts, Index min_cells_per_part) {
  require(num_parts >= 1, "nested_partitions: need at least one part");
  for (const Mesh<dim>& level : h.levels)
    level.require_whole(
        "nested_partitions (a hierarchy built for a partition has its own: MeshHierarchy::partitions)");
  for (int l = 0; l < h.num_levels(); ++l)
    if (h.levels[static_cast<std::size_t>(l)].num_cells() >= min_cells_per_part * num_parts) return l;
  return h.num_levels() - 1;
}
}  // namespace

template <int dim>
MeshHierarchy<dim>::MeshHierarchy(Mesh<dim> coarse, int refinements, const HierarchyPartition& partition) {
  const int parts = partition.parts;
  require(parts >= 1 && partition.rank >= 0 && partition.rank < parts,
          "MeshHierarchy: rank " + std::to_string(partition.rank) + " is not in a partition of " +
              std::to_string(parts) + " parts");
  if (refinements < 0)
    throw Error("MeshHierarchy: negative number of refinements " + std::to_string(refinements));
  // The base level (cut along the Morton curve; the finer levels inherit):
  // the coarsest with enough cells per part, known from the cell counts alone.
  int base = 0;
  if (parts > 1) {
    Index cells = coarse.num_cells();
    while (base < refinements && cells < partition.min_cells_per_part * parts)
      cells *= RefinedMesh<dim>::children_per_cell, ++base;
  }
  const bool partial = partition.partial_levels && parts > 1 && base < refinements;
  const int whole = partial ? base : refinements;  // levels 0 … whole are whole meshes
  levels.reserve(static_cast<std::size_t>(refinements) + 1);
  transfers.reserve(static_cast<std::size_t>(refinements));
  levels.push_back(std::move(coarse));
  std::optional<EdgeNumbering> edges = refine_whole(whole, refinements);
  partitions.resize(static_cast<std::size_t>(refinements) + 1);
  for (int l = 0; l <= base; ++l) {
    const Mesh<dim>& mesh = levels[static_cast<std::size_t>(l)];
    partitions[static_cast<std::size_t>(l)].cell_owner = cut_level(mesh, parts);
  }
  const std::vector<int>& base_owner = partitions[static_cast<std::size_t>(base)].cell_owner;
  if (!partial) {
    for (int l = base + 1; l <= refinements; ++l)
      partitions[static_cast<std::size_t>(l)].blocks = nested_blocks(*this, base, l, base_owner);
    return;
  }
  std::vector<NestedBlocks> blocks;
  refine_partially(*this, base_owner, partition.rank, refinements - base, blocks, edges ? &*edges : nullptr);
  for (std::size_t k = 0; k < blocks.size(); ++k)
    partitions[static_cast<std::size_t>(base) + 1 + k].blocks = std::move(blocks[k]);
}

template <int dim>
std::vector<std::vector<int>> nested_partitions(const MeshHierarchy<dim>& h, int num_parts,
                                                Index min_cells_per_part) {
  const int base = partition_base_level(h, num_parts, min_cells_per_part);
  std::vector<std::vector<int>> owners(static_cast<std::size_t>(h.num_levels()));
  for (int l = 0; l < h.num_levels(); ++l) {
    const Mesh<dim>& mesh = h.levels[static_cast<std::size_t>(l)];
    auto& owner = owners[static_cast<std::size_t>(l)];
    if (num_parts == 1)
      owner.assign(static_cast<std::size_t>(mesh.num_cells()), 0);
    else if (l <= base)
      owner = partition_cells(mesh, num_parts);
    else
      owner = inherit_partition(owners[static_cast<std::size_t>(l - 1)], RefinedMesh<dim>::children_per_cell);
  }
  return owners;
}

template <int dim>
std::vector<LevelPartition> nested_level_partitions(const MeshHierarchy<dim>& h, int num_parts,
                                                    Index min_cells_per_part) {
  const int base = partition_base_level(h, num_parts, num_parts == 1 ? 0 : min_cells_per_part);
  std::vector<LevelPartition> levels(static_cast<std::size_t>(h.num_levels()));
  for (int l = 0; l <= base; ++l) {
    const Mesh<dim>& mesh = h.levels[static_cast<std::size_t>(l)];
    levels[static_cast<std::size_t>(l)].cell_owner = cut_level(mesh, num_parts);
  }
  for (int l = base + 1; l < h.num_levels(); ++l)
    levels[static_cast<std::size_t>(l)].blocks =
        nested_blocks(h, base, l, levels[static_cast<std::size_t>(base)].cell_owner);
  return levels;
}

template struct MeshHierarchy<2>;
template struct MeshHierarchy<3>;
template std::vector<std::vector<int>> nested_partitions(const MeshHierarchy<2>&, int, Index);
template std::vector<std::vector<int>> nested_partitions(const MeshHierarchy<3>&, int, Index);
template std::vector<LevelPartition> nested_level_partitions(const MeshHierarchy<2>&, int, Index);
template std::vector<LevelPartition> nested_level_partitions(const MeshHierarchy<3>&, int, Index);

}  // namespace warpfem::fem
