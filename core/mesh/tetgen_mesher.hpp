#pragma once
// Tetrahedral meshes of a polyhedron by TetGen (the only file that includes
// tetgen.h). By default the surface is kept as given (TetGen's -Y): the
// boundary facets of the mesh are exactly the polyhedron's triangles. TetGen
// then inserts no point that would split the surface, which leaves cells near
// it unrefined (a cube's six sides give six tetrahedra whatever the bounds);
// with keep_surface = false TetGen may split the triangles too, and every
// boundary facet still carries the tag of the triangle it lies in.

#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polyhedron.hpp"

namespace warpfem {

struct TetrahedralMeshOptions {
  /// TetGen's radius-edge ratio bound (-q); 0 means no quality refinement.
  /// Values below 1.2 may keep TetGen from terminating and are refused.
  double quality_ratio = 2.0;
  /// Lower bound on dihedral angles in degrees (-q ratio/angle), against
  /// slivers; 0 means none. Only with quality_ratio > 0; TetGen may not reach
  /// bounds above ~18°.
  double min_dihedral_angle = 0.0;
  /// Upper bound on the tetrahedron volume (-a); <= 0 means none. With
  /// keep_surface, cells near the surface may exceed it.
  double max_volume = 0.0;
  /// Tag of each input triangle (e.g. a part id); empty means the triangle's
  /// index. Carried over to the boundary facet made of that triangle.
  std::vector<int> triangle_tags;
  /// Boundary facets are exactly the input triangles (no point on the surface is added).
  bool keep_surface = true;
};

/// Tetrahedralizes the (validated) polyhedron: cells positively oriented,
/// the polyhedron's vertices are the first mesh vertices in their order,
/// boundary facets outward with the tags of their input triangles. Throws
/// warpfem::Error naming the polyhedron and a fix when the options are
/// invalid or TetGen fails.
Mesh<3> mesh_polyhedron(const Polyhedron& polyhedron, const TetrahedralMeshOptions& options = {});

}  // namespace warpfem
