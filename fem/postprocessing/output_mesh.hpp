#pragma once
// The warped mesh as it is written for visualization: the local cells of this
// rank as Lagrange cells of order `order` whose nodes are placed by f, so
// curved cells are shown curved (order 2 for any non-affine map): VTK Lagrange
// triangles and quadrilaterals in 2D, tetrahedra and hexahedra in 3D. Fields
// of a finite element function are evaluated at these nodes.

#include <vector>

#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

template <int dim>
struct OutputMesh {
  CellType cell_type = dim == 2 ? CellType::triangle : CellType::tetrahedron;
  int order = 1;
  Points<dim> reference_points;  ///< node positions in Ω0
  Points<dim> points;            ///< node positions f(x0) in Ω1
  VectorX map_det;               ///< det J_f at the nodes
  IndexTable cells;              ///< local cells x nodes, VTK Lagrange node order
  /// Quadratic quadrilateral and hexahedral output only: pieces written as
  /// straight-sided quadratic triangles or tetrahedra (VTK Lagrange order),
  /// after the rows of `cells`.
  IndexTable simplex_cells;
  std::vector<Index> cell_ids;      ///< mesh cell id of every output cell (`cells`, then `simplex_cells`)
  std::vector<Index> source_cells;  ///< index into the local cells of every output cell (same order)
  /// Mesh cells whose curved geometry folded and were written as smaller
  /// curved cells (2D); output cells whose nodes were pulled toward their
  /// straight cell because they still folded; quadrilaterals written as
  /// straight triangles because even their straight cell folded; output
  /// cells written folded.
  Index num_mesh_cells = 0, num_subdivided_cells = 0, num_straightened_cells = 0, num_split_cells = 0,
        num_tangled_cells = 0;
  /// Straight pieces below 1e-6 of their cell's size that f still folds (next
  /// to points where it is not differentiable) and are left out of the
  /// output, and their total volume in units of a cell's volume.
  Index num_left_out_pieces = 0;
  double left_out_volume = 0;

  Index num_cells() const { return cells.rows() + simplex_cells.rows(); }

  /// A per-local-cell field spread onto the output cells (pieces of a
  /// subdivided cell get their cell's value).
  std::vector<double> cell_values(const VectorX& per_local_cell) const;

  /// Values at the nodes of the FE function with coefficients `relevant_values`
  /// (ordered as dist.relevant_dofs()), in the form a VTK field takes them.
  std::vector<double> interpolate(const DofMap<dim>& dofs, const DofDistribution<dim>& dist,
                                  const VectorX& relevant_values) const;

 private:
  template <int d>
  friend OutputMesh<d> make_output_mesh(const Mesh<d>&, const DofDistribution<d>&, const mapping::Map<d>&,
                                        int);
  struct NodeSource {
    Index cell;     ///< mesh cell the node lies in
    Point<dim> xi;  ///< its reference coordinates in that cell
  };
  /// Where the FE function is evaluated: for the nodes of the mesh cells,
  /// mesh cell × nodes per cell + the node's place in that cell (the first
  /// cell that reaches it); for the nodes that subdivision adds after them,
  /// their cell and reference point.
  std::vector<Index> node_in_cell_;
  std::vector<NodeSource> added_node_source_;
};

/// Builds the output mesh of the cells owned by this rank. `order` 0 picks
/// max(element order, 1 if f is affine else 2). A 2D cell whose curved
/// geometry would fold (det of its geometric Jacobian ≤ 0 at a node or on a
/// lattice of its reference cell) is split into four, recursively up to four
/// times, with every node placed by f. A cell that still folds (2D at the
/// depth limit, 3D at once) has its non-vertex nodes pulled toward the straight
/// cell of its mapped vertices until it does not, unless that leaves more
/// folded cells around it than before. A quadratic quadrilateral whose straight
/// cell folds too (f opens a corner of Ω0 into a reflex corner of Ω1, or turns
/// sharply inside it) is written as triangles first: cut along a diagonal, or a
/// triangulation of its mapped boundary. Quadrilaterals, triangles and
/// tetrahedra that still fold are written as straight simplices placed by f,
/// bisected across f's sweep until every one is positive (pieces below 1e-6
/// of the cell that still fold are left out). What still folds is counted in
/// num_tangled_cells.
template <int dim>
OutputMesh<dim> make_output_mesh(const Mesh<dim>& mesh, const DofDistribution<dim>& dist,
                                 const mapping::Map<dim>& map, int order);

/// Logs (collectively over `comm`) how many mesh cells were subdivided to keep
/// the written cells untangled, and warns about any that still fold.
template <int dim>
void log_untangling(MPI_Comm comm, const OutputMesh<dim>& out);

}  // namespace warpfem::fem
