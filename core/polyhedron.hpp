#pragma once
// A polyhedron given by its boundary: a closed triangulated surface whose
// triangles are oriented outward (counter-clockwise seen from outside).
//
// Validation combines exact CGAL predicates (degenerate triangles, self-
// intersections, orientation) with a combinatorial check of the triangle
// list (indices, closedness, edge and vertex manifoldness), and each failure
// names the triangles or vertices concerned and how to repair them.

#include <array>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace warpfem {

class Polyhedron {
 public:
  using Triangle = std::array<Index, 3>;

  Polyhedron() = default;
  /// Stores the surface; call validate() (or use Polyhedron::checked) before use.
  Polyhedron(std::vector<Point<3>> vertices, std::vector<Triangle> triangles,
             std::string name = "polyhedron");

  /// Builds and validates; throws warpfem::Error naming `name` on failure.
  static Polyhedron checked(std::vector<Point<3>> vertices, std::vector<Triangle> triangles,
                            std::string name = "polyhedron");

  /// Reads an OFF, OBJ, STL or PLY surface (CGAL's readers) and validates it;
  /// errors name the file.
  static Polyhedron read(const std::string& path);

  /// Throws warpfem::Error unless the surface is a closed, connected,
  /// 2-manifold, outward-oriented triangulation without degenerate
  /// triangles or self-intersections, using every vertex.
  void validate() const;

  Index vertex_count() const { return static_cast<Index>(vertices_.size()); }
  Index triangle_count() const { return static_cast<Index>(triangles_.size()); }
  const Point<3>& vertex(Index i) const { return vertices_[static_cast<std::size_t>(i)]; }
  const Triangle& triangle(Index t) const { return triangles_[static_cast<std::size_t>(t)]; }
  const std::vector<Point<3>>& vertices() const { return vertices_; }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  const std::string& name() const { return name_; }

  /// Boundary-part id of each triangle, as the config or the surface file gave
  /// them (ids 0..K-1, each used); empty when none were given, and the parts
  /// are the planar face groups (fem/hierarchy/polyhedron_parts.hpp).
  const std::vector<int>& triangle_parts() const { return triangle_parts_; }
  /// Sets the parts; throws warpfem::Error naming the polyhedron unless there is
  /// one id per triangle and the ids are 0..K-1, each used.
  void set_triangle_parts(std::vector<int> parts);

  /// Enclosed volume (positive for outward orientation).
  Real signed_volume() const;
  Real surface_area() const;
  Point<3> bbox_min() const;
  Point<3> bbox_max() const;

  /// The same surface with every triangle reversed.
  Polyhedron reversed() const;

 private:
  std::vector<Point<3>> vertices_;
  std::vector<Triangle> triangles_;
  std::string name_ = "polyhedron";
  std::vector<int> triangle_parts_;
};

/// Throws warpfem::Error unless `source` and `target` have the same vertex
/// count and the same triangles (the vertex correspondence of a map).
void require_same_triangulation(const Polyhedron& source, const Polyhedron& target);

/// Generalized winding number of the surface around x (Van Oosterom–Strackee
/// solid angles): 1 inside, 0 outside, ½ on a face.
Real winding_number(const Polyhedron& polyhedron, const Point<3>& x);

}  // namespace warpfem
