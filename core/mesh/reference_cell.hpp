#pragma once
// Topology of the reference cells: cell types, their edges and their facets.
//
// Local numbering follows VTK's cells (vtkTriangle, vtkQuad, vtkTetra,
// vtkHexahedron and their Lagrange variants), so output needs no permutation:
//   triangle      (0,0) (1,0) (0,1)
//   quadrilateral (0,0) (1,0) (1,1) (0,1)
//   tetrahedron   (0,0,0) (1,0,0) (0,1,0) (0,0,1)
//   hexahedron    (0,0,0) (1,0,0) (1,1,0) (0,1,0), then the same at z = 1

#include <array>
#include <string>
#include <vector>

namespace warpfem {

enum class CellType { triangle, quadrilateral, tetrahedron, hexahedron };

constexpr int vertices_per_cell(CellType t) {
  switch (t) {
    case CellType::triangle: return 3;
    case CellType::quadrilateral: return 4;
    case CellType::tetrahedron: return 4;
    case CellType::hexahedron: return 8;
  }
  return 0;
}
constexpr int cell_dimension(CellType t) {
  return (t == CellType::triangle || t == CellType::quadrilateral) ? 2 : 3;
}
std::string to_string(CellType t);

/// Local vertex pairs of the edges of a cell, in the order used for edge DOFs
/// (and by VTK's Lagrange cells): triangle (0,1),(1,2),(2,0); quad
/// (0,1),(1,2),(2,3),(3,0); tetrahedron (0,1),(1,2),(2,0),(0,3),(1,3),(2,3);
/// hexahedron bottom cycle, top cycle (4,5),(5,6),(6,7),(7,4), then the
/// vertical edges (0,4),(1,5),(2,6),(3,7). VTK orients hexahedron edges 2 and 6
/// (and the quad's last two) along the axes instead; with one node per edge
/// the orientation does not matter.
const std::vector<std::array<int, 2>>& cell_edges(CellType t);

/// Local vertex lists of the facets (codimension-1 faces) of a cell, oriented
/// outward (counter-clockwise seen from outside the cell), in VTK's order.
/// 2D cells: the edges of cell_edges(). Tetrahedron (vtkTetra): (0,1,3),
/// (1,2,3), (2,0,3), (0,2,1). Hexahedron (vtkHexahedron, which is also the face
/// order of the Lagrange hexahedron's face nodes): x=0 (0,4,7,3), x=1
/// (1,2,6,5), y=0 (0,1,5,4), y=1 (3,7,6,2), z=0 (0,3,2,1), z=1 (4,5,6,7).
const std::vector<std::vector<int>>& cell_faces(CellType t);

/// Cell type of the facets of a 3D cell: triangle for a tetrahedron,
/// quadrilateral for a hexahedron. Throws for 2D cells (their facets are edges).
CellType facet_type(CellType t);

}  // namespace warpfem
