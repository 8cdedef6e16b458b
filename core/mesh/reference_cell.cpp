#include "core/mesh/reference_cell.hpp"

#include "core/error.hpp"

namespace warpfem {

std::string to_string(CellType t) {
  switch (t) {
    case CellType::triangle: return "triangle";
    case CellType::quadrilateral: return "quadrilateral";
    case CellType::tetrahedron: return "tetrahedron";
    case CellType::hexahedron: return "hexahedron";
  }
  return "unknown";
}

const std::vector<std::array<int, 2>>& cell_edges(CellType t) {
  static const std::vector<std::array<int, 2>> tri{{0, 1}, {1, 2}, {2, 0}};
  static const std::vector<std::array<int, 2>> quad{{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  static const std::vector<std::array<int, 2>> tet{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  static const std::vector<std::array<int, 2>> hex{{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                                   {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  switch (t) {
    case CellType::triangle: return tri;
    case CellType::quadrilateral: return quad;
    case CellType::tetrahedron: return tet;
    case CellType::hexahedron: return hex;
  }
  return tri;
}

const std::vector<std::vector<int>>& cell_faces(CellType t) {
  static const std::vector<std::vector<int>> tri{{0, 1}, {1, 2}, {2, 0}};
  static const std::vector<std::vector<int>> quad{{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  static const std::vector<std::vector<int>> tet{{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 2, 1}};
  static const std::vector<std::vector<int>> hex{{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4},
                                                 {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};
  switch (t) {
    case CellType::triangle: return tri;
    case CellType::quadrilateral: return quad;
    case CellType::tetrahedron: return tet;
    case CellType::hexahedron: return hex;
  }
  return tri;
}

CellType facet_type(CellType t) {
  require(cell_dimension(t) == 3, "facet_type: the facets of a " + to_string(t) + " are edges");
  return t == CellType::tetrahedron ? CellType::triangle : CellType::quadrilateral;
}

}  // namespace warpfem
