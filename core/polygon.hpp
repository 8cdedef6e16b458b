#pragma once
// A simple polygon given by its vertices in counter-clockwise order.
//
// Validation uses CGAL's exact predicates, so the verdicts "simple" and
// "counter-clockwise" are exact for the double coordinates given. Collinear
// consecutive vertices are allowed (a square carrying many vertices along its
// sides is the usual parametrization domain).

#include <string>
#include <vector>

#include "core/types.hpp"

namespace warpfem {

class Polygon {
 public:
  Polygon() = default;
  /// Stores the vertices; call validate() (or use Polygon::checked) before use.
  Polygon(std::vector<Point<2>> vertices, std::string name = "polygon");

  /// Builds and validates; throws warpfem::Error naming `name` on failure.
  static Polygon checked(std::vector<Point<2>> vertices, std::string name = "polygon");

  /// Throws warpfem::Error if the polygon has fewer than 3 vertices, a
  /// zero-length edge, a self-intersection, or clockwise orientation.
  void validate() const;

  /// True iff the polygon is strictly convex or convex with collinear vertices.
  bool is_convex() const;

  Index size() const { return static_cast<Index>(vertices_.size()); }
  const Point<2>& vertex(Index i) const { return vertices_[static_cast<std::size_t>(wrap(i))]; }
  const std::vector<Point<2>>& vertices() const { return vertices_; }
  const std::string& name() const { return name_; }

  /// Index modulo size(), also for negative i.
  Index wrap(Index i) const {
    const Index n = size();
    return ((i % n) + n) % n;
  }

  /// Signed area (positive for counter-clockwise order).
  Real signed_area() const;
  Real perimeter() const;
  /// Smallest and largest corner of the bounding box.
  Point<2> bbox_min() const;
  Point<2> bbox_max() const;

  /// Exact test: -1 outside, 0 on the boundary, +1 inside.
  int side_of(const Point<2>& p) const;
  /// side_of for many points (the vertices converted once).
  std::vector<int> side_of(const std::vector<Point<2>>& points) const;

  /// Returns the polygon with reversed vertex order (vertex 0 stays first).
  Polygon reversed() const;

 private:
  std::vector<Point<2>> vertices_;
  std::string name_ = "polygon";
};

/// Throws warpfem::Error unless `source` and `target` have the same number of vertices.
void require_same_vertex_count(const Polygon& source, const Polygon& target);

}  // namespace warpfem
