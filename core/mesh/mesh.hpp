#pragma once
// A conforming mesh of the parametrization domain Ω0 (the "simple" mesh).
//
// A mesh is the same on every MPI rank (the coarse description of Ω0 and its
// uniform refinements), except the fine levels of a MeshHierarchy built for a
// partition, which each rank stores only around its own cells (`partial`);
// ownership of cells and DOFs is decided by fem::DofDistribution.
// Boundary facets carry the index of the source-polygon edge they lie on,
// which is also the index of the corresponding target edge, so boundary
// conditions can select "target-polygon edges".

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "core/mesh/reference_cell.hpp"
#include "core/types.hpp"

namespace warpfem {

/// Entry type of mesh and DOF tables: 32-bit, which halves the memory (and the
/// first-touch and bandwidth cost) of the largest arrays of a refined
/// hierarchy. Meshes are limited to 2^31 - 1 vertices / DOFs per rank
/// (checked where tables are built: refine_uniformly, DofMap).
using TableIndex = std::int32_t;
/// `count` as a TableIndex, or an error naming `what` when it does not fit.
TableIndex checked_table_size(Index count, const std::string& what);
/// Row-major integer table: one row per cell (or facet).
using IndexTable = Eigen::Matrix<TableIndex, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

template <int dim>
struct Mesh {
  CellType cell_type = dim == 2 ? CellType::triangle : CellType::tetrahedron;
  Points<dim> vertices;         ///< N x dim, coordinates in Ω0
  IndexTable cells;             ///< cells x vertices_per_cell(cell_type), counter-clockwise in 2D
  IndexTable boundary_facets;   ///< boundary facets x facet vertices, outward (see cell_faces)
  std::vector<int> facet_tags;  ///< per boundary facet: index of the polygon edge (face) it lies on

  /// A level one rank refined only around its own cells (a MeshHierarchy
  /// built for a partition, fem/partial_refinement.hpp): the tables keep the
  /// whole level's size and numbering, but only the cells in `present_cells`
  /// (ranges [first, last)) and their vertices are stored; the memory of the
  /// other rows is never written (nor touched). Boundary facets outside the
  /// rank's region are rows (-1, -1). A whole mesh has partial = false.
  bool partial = false;
  std::vector<std::array<Index, 2>> present_cells;

  Index num_vertices() const { return vertices.rows(); }
  Index num_cells() const { return cells.rows(); }
  Index num_boundary_facets() const { return boundary_facets.rows(); }
  Point<dim> vertex(Index i) const { return vertices.row(i).transpose(); }
  /// The stored cells as ranges [first, last): {{0, num_cells()}} for a whole mesh.
  std::vector<std::array<Index, 2>> cell_ranges() const;
  /// Whether boundary facet f is stored (always, in a whole mesh).
  bool has_facet(Index f) const { return boundary_facets(f, 0) >= 0; }
  /// Throws warpfem::Error naming `what` unless the whole mesh is stored
  /// (for algorithms that visit every cell).
  void require_whole(const std::string& what) const;
  /// Largest edge length over the stored cells (all cells of a whole mesh).
  Real max_edge_length() const;
};

}  // namespace warpfem
