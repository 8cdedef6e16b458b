#pragma once
// Builds the simple (coarse) mesh of Ω0 a config asks for.

#include <string>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"
#include "core/polyhedron.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

/// The simple mesh of Ω0 a config asks for: one struct for both dimensions;
/// io::parse_mesh_spec refuses the fields and values of the other dimension.
struct MeshSpec {
  /// 2D — delaunay: CGAL constrained Delaunay triangles; quad_split: the
  /// Delaunay triangles split into 3 quadrilaterals each; structured: an nx x ny
  /// grid of the (rectangular) source polygon; gmsh: read from `file`;
  /// pullback: CGAL's Delaunay mesh of the *target* polygon pulled back through
  /// f⁻¹ (fem/pullback_mesher.hpp; triangles, or quadrilaterals by splitting).
  /// 3D — tetgen: TetGen's tetrahedra of the source polyhedron; structured: an
  /// nx x ny x nz grid of a box-shaped source polyhedron; gmsh: tetrahedra or
  /// hexahedra read from `file`.
  std::string type = "delaunay";
  CellType cell_type = CellType::triangle;  ///< structured, pullback: the cells
  double max_edge_length = 0;     ///< delaunay/quad_split/pullback: 0 = meshed polygon's bbox diagonal / 10
  double shape_bound = 0.125;     ///< delaunay/quad_split/pullback: CGAL shape bound
  int nx = 4, ny = 4, nz = 4;     ///< structured: cells per direction (nz: 3D)
  double quality_ratio = 2.0;     ///< tetgen: radius-edge ratio bound (-q)
  double min_dihedral_angle = 0;  ///< tetgen: dihedral angle bound in degrees (-q ratio/angle); 0 = none
  double max_volume = 0;          ///< tetgen: volume bound (-a); 0 = none
  bool keep_surface = true;       ///< tetgen: boundary facets are the surface's triangles (-Y)
  std::string file;               ///< gmsh: path of the .msh file
  int refinements = 0;            ///< uniform refinements of the generated mesh
  /// gmsh in 3D, found when the config is read: the file's cells and the
  /// boundary parts its physical groups give (0: the source polyhedron's parts).
  Index file_cells = 0;
  int file_parts = 0;
};

/// The coarse mesh (before refinements) of a type that does not need the map.
Mesh<2> make_coarse_mesh(const Polygon& source, const MeshSpec& spec);

/// The coarse mesh for the map f: `source` → `target`; any type, "pullback" included.
Mesh<2> make_coarse_mesh(const Polygon& source, const Polygon& target, const mapping::Map<2>& map,
                         const MeshSpec& spec);

/// True if the polyhedron is its bounding box (every vertex on the box's
/// surface, the same volume): what mesh type "structured" grids in 3D.
bool is_axis_aligned_box(const Polyhedron& polyhedron);

/// The coarse mesh of a polyhedron: TetGen's tetrahedra, a structured grid of
/// a box, or a Gmsh file's cells. Boundary facets are tagged with the boundary
/// parts of `source` (fem/hierarchy/polyhedron_parts.hpp), or with the Gmsh
/// file's physical groups when it has them. `target` and `map` are not used by
/// these types; they keep the call the same in both dimensions.
Mesh<3> make_coarse_mesh(const Polyhedron& source, const Polyhedron& target, const mapping::Map<3>& map,
                         const MeshSpec& spec);

}  // namespace warpfem::fem
