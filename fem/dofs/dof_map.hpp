#pragma once
// Mesh-wide numbering of the DOFs of a Lagrange space (serial numbering,
// identical on every rank): vertex v -> v, edge node e -> nv + e, cell-interior
// node of cell c -> nv + ne + c. fem::DofDistribution turns it into the
// parallel PETSc numbering.
//
// For P1/Q1 the DOF table and the node positions *are* the mesh's cell table
// and vertices: the DofMap refers to them instead of copying (the mesh must
// outlive the DofMap, as it must for every user of both).

#include <memory>
#include <optional>
#include <vector>

#include "core/mesh/edge_numbering.hpp"
#include "core/mesh/mesh.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

class DofMap {
 public:
  /// `mesh` must outlive the DofMap (P1/Q1 refer to its cells and vertices).
  DofMap(const Mesh<2>& mesh, const LagrangeElement<2>& element);

  Index num_dofs() const { return num_dofs_; }
  const LagrangeElement<2>& element() const { return element_; }
  /// cells x element().num_dofs() table of DOF ids.
  const IndexTable& cell_dofs() const { return vertex_dofs_ ? vertex_dofs_->cells : cell_dofs_; }
  /// Position of every DOF node in Ω0 (num_dofs x 2).
  const Points<2>& dof_points() const { return vertex_dofs_ ? vertex_dofs_->vertices : dof_points_; }
  /// P1/Q1: DOF v is mesh vertex v (cell_dofs() is the mesh's cell table).
  bool dofs_are_vertices() const { return vertex_dofs_ != nullptr; }
  /// DOFs on boundary facet f, ordered (start vertex, end vertex, interior nodes).
  std::vector<Index> facet_dofs(const Mesh<2>& mesh, Index facet) const;

 private:
  LagrangeElement<2> element_;
  std::optional<EdgeNumbering> edges_;  // only for elements with edge DOFs (P2, Q2)
  Index num_dofs_ = 0;
  const Mesh<2>* vertex_dofs_ = nullptr;  // P1/Q1: the DOFs are this mesh's vertices
  IndexTable cell_dofs_;                  // otherwise
  Points<2> dof_points_;
};

}  // namespace warpfem::fem
