#pragma once
// Builds the simple (coarse) mesh of Ω0 a config asks for.

#include <string>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

struct MeshSpec {
  /// delaunay: CGAL constrained Delaunay triangles; quad_split: the Delaunay
  /// triangles split into 3 quadrilaterals each; structured: an nx x ny grid
  /// of the (rectangular) source polygon; gmsh: read from `file`; pullback:
  /// CGAL's Delaunay mesh of the *target* polygon pulled back through f⁻¹
  /// (fem/pullback_mesher.hpp; triangles, or quadrilaterals by splitting).
  std::string type = "delaunay";
  CellType cell_type = CellType::triangle;  ///< structured, pullback: triangle or quadrilateral
  double max_edge_length = 0;  ///< delaunay/quad_split/pullback: 0 = meshed polygon's bbox diagonal / 10
  double shape_bound = 0.125;  ///< delaunay/quad_split/pullback: CGAL shape bound
  int nx = 4, ny = 4;          ///< structured: cells per direction
  std::string file;            ///< gmsh: path of the .msh file
  int refinements = 0;         ///< uniform refinements of the generated mesh
};

/// The coarse mesh (before refinements) of a type that does not need the map.
Mesh<2> make_coarse_mesh(const Polygon& source, const MeshSpec& spec);

/// The coarse mesh for the map f: `source` → `target`; any type, "pullback" included.
Mesh<2> make_coarse_mesh(const Polygon& source, const Polygon& target, const mapping::Map<2>& map,
                         const MeshSpec& spec);

}  // namespace warpfem::fem
