#pragma once
// An auxiliary triangle mesh of a polygon, used by the P1 harmonic solve and by
// the piecewise-linear seed of the inverse (thesis §5.1.1, §5.2). Built with
// CGAL's constrained Delaunay mesher; only mapping/harmonic uses it (the FEM
// meshes of fem/ are a different thing).

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/polygon.hpp"
#include "core/types.hpp"
#include "mapping/harmonic/boundary_data.hpp"

namespace warpfem::mapping {

struct TriangleMesh {
  Points<2> vertices;                           ///< nv x 2
  std::vector<std::array<Index, 3>> triangles;  ///< counter-clockwise vertex indices
  /// at[v] is the position of vertex v on ∂Ω; on_boundary[v] says whether it is there.
  std::vector<BoundaryPoint> at;
  std::vector<bool> on_boundary;
  /// neighbors[t][i] is the triangle across the edge opposite vertex i, or -1 on ∂Ω.
  std::vector<std::array<Index, 3>> neighbors;

  Index num_vertices() const { return vertices.rows(); }
  Index num_triangles() const { return static_cast<Index>(triangles.size()); }
};

/// Constrained Delaunay mesh of `domain` with edges at most `max_edge_length`
/// (and angles ≥ ~20.7°). The boundary is first split into equal pieces no
/// longer than max_edge_length, so every polygon vertex is a mesh vertex.
/// Throws warpfem::Error if the mesh would exceed `max_triangles`.
TriangleMesh mesh_polygon(const Polygon& domain, Real max_edge_length, Index max_triangles = 2'000'000);

}  // namespace warpfem::mapping
