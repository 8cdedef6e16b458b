#pragma once
// Point location in a mesh of Ω0: which cell contains a point, and where in
// the reference cell. A uniform bucket grid over the cells' bounding boxes
// keeps queries O(1) on average. Used to evaluate functions of one level at
// points of another (nested levels, reference solutions) and for the
// piecewise-linear interpolant of a map (the standard-FEM baseline).

#include <vector>

#include "core/mesh/mesh.hpp"

namespace warpfem {

class CellLocator {
 public:
  explicit CellLocator(const Mesh<2>& mesh);

  struct Location {
    Index cell = -1;  ///< -1: not found
    Point<2> xi;      ///< reference coordinates in the cell
  };
  /// Finds a cell containing x (within a small tolerance, so boundary points are found).
  Location locate(const Point<2>& x) const;

 private:
  bool inside(Index cell, const Point<2>& x, Point<2>& xi) const;
  const Mesh<2>& mesh_;
  Point<2> lo_, cell_size_;
  int nx_ = 1, ny_ = 1;
  std::vector<Index> start_, items_;
};

}  // namespace warpfem
