#pragma once
// Mesh-wide numbering of the DOFs of a Lagrange space (serial numbering,
// identical on every rank), by mesh entity: vertex v -> v, the node of edge e
// -> nv + e, the node of face f (Q2 hexahedra: the face centre) -> nv + ne + f,
// the interior nodes of cell c -> nv + ne + nf + c * interior + k. 2D meshes
// number no faces (nf = 0). Edges and faces are numbered in the order the
// cells first use them (EdgeNumbering, FaceNumbering). At most one node per
// edge and face (orders ≤ 2), so no orientation is needed. fem::DofDistribution
// turns it into the parallel PETSc numbering.
//
// For P1/Q1 the DOF table and the node positions *are* the mesh's cell table
// and vertices: the DofMap refers to them instead of copying (the mesh must
// outlive the DofMap, as it must for every user of both).

#include <optional>
#include <vector>

#include "core/mesh/edge_numbering.hpp"
#include "core/mesh/face_numbering.hpp"
#include "core/mesh/mesh.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

template <int dim>
class DofMap {
 public:
  /// `mesh` must outlive the DofMap (P1/Q1 refer to its cells and vertices).
  DofMap(const Mesh<dim>& mesh, const LagrangeElement<dim>& element);

  Index num_dofs() const { return num_dofs_; }
  const LagrangeElement<dim>& element() const { return element_; }
  /// cells x element().num_dofs() table of DOF ids.
  const IndexTable& cell_dofs() const { return vertex_dofs_ ? vertex_dofs_->cells : cell_dofs_; }
  /// Position of every DOF node in Ω0 (num_dofs x dim).
  const Points<dim>& dof_points() const { return vertex_dofs_ ? vertex_dofs_->vertices : dof_points_; }
  /// P1/Q1: DOF v is mesh vertex v (cell_dofs() is the mesh's cell table).
  bool dofs_are_vertices() const { return vertex_dofs_ != nullptr; }
  /// Edges and faces of the mesh that carry DOFs (0 when none do).
  Index num_edges() const { return edges_ ? edges_->num_edges() : 0; }
  Index num_faces() const { return faces_ ? faces_->num_faces() : 0; }
  /// DOFs on boundary facet f in the node order of the facet's element (see
  /// fem::facet_dofs): in 2D (start vertex, end vertex, edge node); in 3D the
  /// facet's vertices, its edge nodes in cell_edges(facet type) order, then
  /// its face node.
  std::vector<Index> facet_dofs(const Mesh<dim>& mesh, Index facet) const;

 private:
  LagrangeElement<dim> element_;
  std::optional<EdgeNumbering> edges_;  // only for elements with edge DOFs (P2, Q2)
  std::optional<FaceNumbering> faces_;  // only for elements with face DOFs (Q2 hexahedra)
  Index num_dofs_ = 0;
  const Mesh<dim>* vertex_dofs_ = nullptr;  // P1/Q1: the DOFs are this mesh's vertices
  IndexTable cell_dofs_;                    // otherwise
  Points<dim> dof_points_;
};

}  // namespace warpfem::fem
