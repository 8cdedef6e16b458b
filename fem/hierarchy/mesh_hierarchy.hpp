#pragma once
// Nested meshes of Ω0: level 0 is the coarse mesh, level k + 1 the uniform
// refinement of level k; optionally partitioned over ranks with the fine
// levels stored only around each rank's cells.

#include <optional>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/hierarchy/nested_blocks.hpp"

namespace warpfem::fem {

/// Cells per part on the partitioned base level of a hierarchy (the coarsest
/// level with at least this many cells per part is cut along its Morton curve;
/// finer levels inherit). Finer bases make thinner rings of neighbour blocks
/// around a rank's cells but more blocks; the value was chosen by measurement
/// (BENCHMARKS.md, multigrid under MPI).
inline constexpr Index kBaseCellsPerPart = 1024;

/// For a MeshHierarchy built for one rank of a partition.
struct HierarchyPartition {
  int parts = 1;  ///< number of ranks
  int rank = 0;   ///< the rank the levels are built for
  /// The base level: the coarsest with this many cells per part.
  Index min_cells_per_part = kBaseCellsPerPart;
  /// Build the levels above the base only around the rank's cells (fit for
  /// P1 and Q1: elements with edge DOFs need whole levels).
  bool partial_levels = true;
};

/// Nested meshes: level 0 is the coarse mesh, level k + 1 the uniform refinement of level k.
template <int dim>
struct MeshHierarchy {
  std::vector<Mesh<dim>> levels;
  /// transfers[k] describes how level k + 1 refines level k (where the coarse nodes went; parents of cells by
  /// RefinedMesh::parent_of); its `mesh` member is moved into `levels` and left empty.
  std::vector<RefinedMesh<dim>> transfers;

  MeshHierarchy(Mesh<dim> coarse, int refinements);
  /// The same levels, partitioned as nested_level_partitions() partitions
  /// them (kept in `partitions`), with the levels above the base built only
  /// around `partition.rank`'s cells (partial meshes, fem/partial_refinement.hpp)
  /// when there are several parts; otherwise (or with partial_levels off) whole.
  MeshHierarchy(Mesh<dim> coarse, int refinements, const HierarchyPartition& partition);
  // Movable, not copyable: `partitions` point into `levels` (a moved vector keeps its elements).
  MeshHierarchy(MeshHierarchy&&) = default;
  MeshHierarchy& operator=(MeshHierarchy&&) = default;
  MeshHierarchy(const MeshHierarchy&) = delete;
  MeshHierarchy& operator=(const MeshHierarchy&) = delete;
  /// Every level's partition (the partitioned constructor only; else empty).
  std::vector<LevelPartition> partitions;
  const Mesh<dim>& finest() const { return levels.back(); }
  int num_levels() const { return static_cast<int>(levels.size()); }

 private:
  /// Appends `count` whole refinements of the finest level, of `total` to come;
  /// returns the last new level's edge numbering if a further refinement needs it.
  std::optional<EdgeNumbering> refine_whole(int count, int total);
};

/// Cell owners for every level of `h` (the same on every rank, no communication):
/// the coarsest level with at least `min_cells_per_part` cells per part, and every
/// coarser one, is cut along its Morton curve (partition_cells); each finer level
/// inherits its parents' owners (inherit_partition). The partition of the fine
/// levels is therefore nested (a rank's fine cells cover its coarse cells, so
/// only prolongation rows along the interface read other ranks' coarse DOFs)
/// and balanced to one base cell's descendants; the per-level Morton sort of
/// the large levels is skipped.
template <int dim>
std::vector<std::vector<int>> nested_partitions(const MeshHierarchy<dim>& h, int num_parts,
                                                Index min_cells_per_part = kBaseCellsPerPart);

/// The same partition, with the levels above the base described as
/// NestedBlocks (no per-cell owner lists for the large levels). One part: the
/// base is level 0.
template <int dim>
std::vector<LevelPartition> nested_level_partitions(const MeshHierarchy<dim>& h, int num_parts,
                                                    Index min_cells_per_part = kBaseCellsPerPart);

}  // namespace warpfem::fem
