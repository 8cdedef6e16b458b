#pragma once
// Point location in a triangle mesh whose vertices may be moved (the image of
// a mesh under a harmonic map): a uniform bucket grid over the triangles'
// bounding boxes. Used for FEM evaluation and for the piecewise-linear inverse
// of thesis §5.2.

#include <array>
#include <vector>

#include "core/types.hpp"

namespace warpfem::mapping {

class TriangleLocator {
 public:
  /// `vertices` (nv x 2) and counter-clockwise `triangles`; both are copied.
  TriangleLocator(const Points<2>& vertices, const std::vector<std::array<Index, 3>>& triangles);

  struct Hit {
    Index triangle = -1;
    std::array<Real, 3> bary{};  ///< barycentric coordinates, clamped to ≥ 0 when outside
    bool inside = false;         ///< false: p lies outside every triangle; the nearest one is returned
  };

  /// The triangle containing p (up to round-off), else the triangle whose
  /// barycentric coordinates are least negative among the nearby ones.
  Hit locate(const Point<2>& p) const;

  /// Barycentric coordinates of p in triangle t (not clamped).
  std::array<Real, 3> barycentric(Index t, const Point<2>& p) const;

 private:
  Points<2> v_;
  std::vector<std::array<Index, 3>> tri_;
  Point<2> lo_, cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<Index> start_, items_;  // CSR buckets
};

}  // namespace warpfem::mapping
