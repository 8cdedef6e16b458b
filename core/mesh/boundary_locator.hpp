#pragma once
// Which edges of the source polygon a boundary point of Ω0 lies on.
//
// Boundary conditions select "target-polygon edges" by index; edge i of the
// target is the image of edge i of the source. When the simple mesh is much
// coarser than the polygon (a 4x4 grid on a square carrying 64 vertices), one
// mesh facet spans several polygon edges, so selection is made per point
// (per DOF node and per boundary quadrature point), not per facet. Every
// level of a multigrid hierarchy asks for each of its boundary points, so
// polygons of many edges find them in CGAL's AABB tree, not by a scan.

#include <memory>
#include <vector>

#include "core/polygon.hpp"

namespace warpfem {

class BoundaryLocator {
 public:
  explicit BoundaryLocator(const Polygon& source, double relative_tolerance = 1e-9);

  /// Edges containing x0, in increasing order (two at a polygon vertex, one
  /// elsewhere on the boundary, none off the boundary). Safe to call from
  /// several threads at once.
  void edges_at(const Point<2>& x0, std::vector<int>& edges) const;
  /// The edge containing x0 that is nearest (for points inside an edge); -1 if none.
  int edge_at(const Point<2>& x0) const;
  Index num_edges() const { return polygon_.size(); }

 private:
  struct EdgeTree;
  /// The edges within (about) the tolerance of x0, in increasing order.
  void candidates(const Point<2>& x0, std::vector<int>& edges) const;

  Polygon polygon_;
  double tolerance_;
  std::shared_ptr<const EdgeTree> tree_;  ///< built and immutable; null for few edges (scanned)
};

}  // namespace warpfem
