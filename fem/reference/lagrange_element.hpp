#pragma once
// Lagrange reference elements: P1, P2 on triangles and tetrahedra, Q1, Q2 on
// quadrilaterals and hexahedra (reference cells in fem/reference_cell.hpp).
//
// Local DOF order is the node order of VTK's Lagrange cells, so output needs no
// permutation: vertices, then one node per edge in cell_edges() order, then
// (Q2 hexahedron) one node per face in cell_faces() order, then the cell
// centre (Q2). For the hexahedron this is vtkHigherOrderHexahedron::
// PointIndexFromIJK of VTK 9 (vertical edges (0,4),(1,5),(2,6),(3,7); face
// nodes x=0, x=1, y=0, y=1, z=0, z=1).

#include <array>
#include <string>
#include <vector>

#include "core/mesh/reference_cell.hpp"
#include "core/types.hpp"

namespace warpfem::fem {

template <int dim>
class LagrangeElement {
 public:
  LagrangeElement(CellType type, int order);

  CellType cell_type() const { return type_; }
  int order() const { return order_; }
  int num_dofs() const { return static_cast<int>(nodes_.rows()); }
  /// Reference coordinates of the nodes (num_dofs x dim).
  const Points<dim>& nodes() const { return nodes_; }
  int num_vertex_dofs() const { return vertices_per_cell(type_); }
  int dofs_per_edge() const { return order_ - 1; }
  /// Nodes inside each facet of a 3D cell (0 for 2D cells, whose facets are edges).
  int dofs_per_face() const { return type_ == CellType::hexahedron && order_ == 2 ? 1 : 0; }
  int interior_dofs() const {
    const int faces = dim == 3 ? static_cast<int>(cell_faces(type_).size()) * dofs_per_face() : 0;
    return num_dofs() - num_vertex_dofs() - static_cast<int>(cell_edges(type_).size()) * dofs_per_edge() -
           faces;
  }

  /// Shape function values at reference points: (points x num_dofs).
  MatrixX values(const Points<dim>& xi) const;
  /// Reference gradients: entry [d] is (points x num_dofs) of d/dxi_d.
  std::array<MatrixX, dim> gradients(const Points<dim>& xi) const;

  std::string name() const;

 private:
  void eval_point(const Real* x, Real* phi, const std::array<Real*, dim>& grad) const;
  CellType type_;
  int order_;
  Points<dim> nodes_;
  /// Tensor-product cells: index of the 1D basis function (0: node 0, 1: node 1,
  /// 2: node 1/2) along each axis, per local node.
  std::vector<std::array<int, dim>> tensor_index_;
};

/// 1D Lagrange shape functions of `order` on [0,1] with nodes ordered
/// (0, 1, interior...) — the trace of LagrangeElement on an edge.
void edge_shape_functions(int order, double s, double* phi);

/// Cell-local DOFs of the nodes on facet `facet` (cell_faces() order), in the
/// node order of the facet's own element: for a 3D cell LagrangeElement<2>(
/// facet_type(cell), order) whose reference vertices map to the facet's
/// vertices in cell_faces() order (so the trace of the cell's shape functions
/// on the facet is that element's); for a 2D cell the edge order of
/// edge_shape_functions (the two ends, then the interior node).
template <int dim>
std::vector<int> facet_dofs(const LagrangeElement<dim>& element, int facet);

}  // namespace warpfem::fem
