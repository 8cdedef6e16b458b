#pragma once
// Builds the simple mesh of Ω0 a config asks for, and its nested hierarchy of
// uniform refinements.

#include <optional>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "fem/mesh.hpp"
#include "fem/nested_blocks.hpp"
#include "fem/uniform_refinement.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

struct MeshSpec {
  /// delaunay: CGAL constrained Delaunay triangles; quad_split: the Delaunay
  /// triangles split into 3 quadrilaterals each; structured: an nx x ny grid
  /// of the (rectangular) source polygon; gmsh: read from `file`; pullback:
  /// CGAL's Delaunay mesh of the *target* polygon pulled back through f⁻¹
  /// (fem/pullback_mesher.hpp; triangles, or quadrilaterals by splitting).
  std::string type = "delaunay";
  CellType cell_type = CellType::triangle;  ///< structured, pullback: triangle or quadrilateral
  double max_edge_length = 0;  ///< delaunay/quad_split/pullback: 0 = meshed polygon's bbox diagonal / 10
  double shape_bound = 0.125;  ///< delaunay/quad_split/pullback: CGAL shape bound
  int nx = 4, ny = 4;          ///< structured: cells per direction
  std::string file;            ///< gmsh: path of the .msh file
  int refinements = 0;         ///< uniform refinements of the generated mesh
};

/// The coarse mesh (before refinements) of a type that does not need the map.
Mesh<2> make_coarse_mesh(const Polygon& source, const MeshSpec& spec);

/// The coarse mesh for the map f: `source` → `target`; any type, "pullback" included.
Mesh<2> make_coarse_mesh(const Polygon& source, const Polygon& target, const mapping::Map<2>& map,
                         const MeshSpec& spec);

/// Cells per part on the partitioned base level of a hierarchy (the coarsest
/// level with at least this many cells per part is cut along its Morton curve;
/// finer levels inherit). Finer bases make thinner rings of neighbour blocks
/// around a rank's cells but more blocks: at 1.24 M P1 DOFs on two ranks,
/// 1024 stored 55 % of the finest cells per rank against 59 % with 256 and set
/// up faster than 256 and 4096 (BENCHMARKS.md, "Session 15").
inline constexpr Index kBaseCellsPerPart = 1024;

/// For a MeshHierarchy built for one rank of a partition.
struct HierarchyPartition {
  int parts = 1;  ///< number of ranks
  int rank = 0;   ///< the rank the levels are built for
  /// The base level: the coarsest with this many cells per part.
  Index min_cells_per_part = kBaseCellsPerPart;
  /// Build the levels above the base only around the rank's cells (triangles;
  /// fit for P1: elements with edge DOFs need whole levels).
  bool partial_levels = true;
};

/// Nested meshes: level 0 is the coarse mesh, level k + 1 the uniform refinement of level k.
struct MeshHierarchy {
  std::vector<Mesh<2>> levels;
  /// transfers[k] describes how level k + 1 refines level k (where the coarse nodes went; parents of cells by
  /// RefinedMesh::parent_of); its `mesh` member is moved into `levels` and left empty.
  std::vector<RefinedMesh> transfers;

  MeshHierarchy(Mesh<2> coarse, int refinements);
  /// The same levels, partitioned as nested_level_partitions() partitions
  /// them (kept in `partitions`), with the levels above the base built only
  /// around `partition.rank`'s cells (partial meshes, fem/partial_refinement.hpp)
  /// when there are several parts and the cells are triangles; otherwise whole.
  MeshHierarchy(Mesh<2> coarse, int refinements, const HierarchyPartition& partition);
  // Movable, not copyable: `partitions` point into `levels` (a moved vector keeps its elements).
  MeshHierarchy(MeshHierarchy&&) = default;
  MeshHierarchy& operator=(MeshHierarchy&&) = default;
  MeshHierarchy(const MeshHierarchy&) = delete;
  MeshHierarchy& operator=(const MeshHierarchy&) = delete;
  /// Every level's partition (the partitioned constructor only; else empty).
  std::vector<LevelPartition> partitions;
  const Mesh<2>& finest() const { return levels.back(); }
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
std::vector<std::vector<int>> nested_partitions(const MeshHierarchy& h, int num_parts,
                                                Index min_cells_per_part = kBaseCellsPerPart);

/// The same partition, with the levels above the base described as
/// NestedBlocks (no per-cell owner lists for the large levels). One part: the
/// base is level 0.
std::vector<LevelPartition> nested_level_partitions(const MeshHierarchy& h, int num_parts,
                                                    Index min_cells_per_part = kBaseCellsPerPart);

}  // namespace warpfem::fem
