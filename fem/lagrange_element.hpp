#pragma once
// Lagrange reference elements P1, P2 (triangles) and Q1, Q2 (quadrilaterals).
//
// Reference cells: triangle {(0,0),(1,0),(0,1)}, quadrilateral [0,1]^2 with
// vertices (0,0),(1,0),(1,1),(0,1). Local DOF order: vertices, then one node
// per edge in cell_edges() order, then the cell centre (Q2) — the node order
// of VTK's Lagrange cells, so output needs no permutation.

#include <vector>

#include "core/types.hpp"
#include "fem/mesh.hpp"

namespace warpfem::fem {

class LagrangeElement {
 public:
  LagrangeElement(CellType type, int order);

  CellType cell_type() const { return type_; }
  int order() const { return order_; }
  int num_dofs() const { return static_cast<int>(nodes_.rows()); }
  /// Reference coordinates of the nodes (num_dofs x 2).
  const Points<2>& nodes() const { return nodes_; }
  int num_vertex_dofs() const { return vertices_per_cell(type_); }
  int dofs_per_edge() const { return order_ - 1; }
  int interior_dofs() const {
    return num_dofs() - num_vertex_dofs() - static_cast<int>(cell_edges(type_).size()) * dofs_per_edge();
  }

  /// Shape function values at reference points: (points x num_dofs).
  MatrixX values(const Points<2>& xi) const;
  /// Reference gradients: entry [d] is (points x num_dofs) of d/dxi_d.
  std::array<MatrixX, 2> gradients(const Points<2>& xi) const;

  std::string name() const;

 private:
  void eval_point(double u, double v, double* phi, double* du, double* dv) const;
  CellType type_;
  int order_;
  Points<2> nodes_;
};

/// 1D Lagrange shape functions of `order` on [0,1] with nodes ordered
/// (0, 1, interior...) — the trace of LagrangeElement on an edge.
void edge_shape_functions(int order, double s, double* phi);

}  // namespace warpfem::fem
