#pragma once
// Point location in a 2D mesh: which cell contains a point, and where in the
// reference cell. A uniform bucket grid over the cells' bounding boxes keeps
// queries O(1) on average. The cells may have moved corners (the image of a
// mesh under a map), so the locator also serves piecewise-linear maps and
// their inverses. Used to evaluate functions of one level at points of
// another (nested levels, reference solutions), for the piecewise-linear
// interpolant of a map (the standard-FEM baseline) and by the P1 harmonic maps.

#include <array>
#include <vector>

#include "core/mesh/mesh.hpp"

namespace warpfem {

class CellLocator {
 public:
  /// Locates in the cells of `mesh`, which must outlive the locator.
  explicit CellLocator(const Mesh<2>& mesh);
  /// Locates in `cells` (of `type`, counter-clockwise) with corners `vertices`;
  /// both must outlive the locator.
  CellLocator(const Points<2>& vertices, const IndexTable& cells, CellType type);

  struct Location {
    Index cell = -1;  ///< -1: not found
    Point<2> xi;      ///< reference coordinates in the cell
  };
  /// Finds a cell containing x (within a small tolerance, so boundary points are found).
  Location locate(const Point<2>& x) const;

  struct Nearest {
    Index cell = -1;
    std::array<Real, 3> barycentric{};  ///< clamped to ≥ 0 and renormalised when x is outside
    bool inside = false;                ///< false: x lies outside every triangle
  };
  /// Triangles only: the triangle containing x up to round-off (of several,
  /// the one whose least barycentric coordinate is largest), else the nearby
  /// triangle whose least barycentric coordinate is largest. Every x gets a triangle.
  Nearest nearest(const Point<2>& x) const;

 private:
  bool inside(Index cell, const Point<2>& x, Point<2>& xi) const;
  const Points<2>& vertices_;
  const IndexTable& cells_;
  CellType type_;
  Point<2> lo_, cell_size_;
  int nx_ = 1, ny_ = 1;
  std::vector<Index> start_, items_;  // cells overlapping bucket b: items_[start_[b] .. start_[b + 1])
};

/// Barycentric coordinates of p in the triangle (a, b, c), not clamped.
std::array<Real, 3> barycentric_coordinates(const Point<2>& a, const Point<2>& b, const Point<2>& c,
                                            const Point<2>& p);

}  // namespace warpfem
