#pragma once
// Boundary parts of a polyhedron Ω0, the 3D counterpart of a polygon's edges:
// the parts the config or the surface file gave (Polyhedron::triangle_parts),
// or else its planar face groups. A planar group is a maximal set of triangles
// connected across edges and lying in one plane (the six sides of a cube,
// however finely each is triangulated); part k is the group whose first
// triangle comes k-th in the surface's triangle list, so the numbering is
// fixed by the surface file and does not depend on the mesh.

#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polyhedron.hpp"

namespace warpfem::fem {

struct PolyhedronParts {
  std::vector<int> triangle_part;  ///< part of each surface triangle
  std::vector<Point<3>> normal;    ///< per part: outward unit normal (area-weighted mean if not planar)
  std::vector<Point<3>> centroid;  ///< per part: area-weighted centroid (for messages)
  bool given = false;              ///< the polyhedron's own parts, not planar face groups
  int count() const { return static_cast<int>(normal.size()); }
};

/// The planar face groups of a (validated) polyhedron.
PolyhedronParts planar_face_groups(const Polyhedron& polyhedron);

/// The boundary parts "faces" name: the polyhedron's triangle_parts() if it
/// has them, else its planar face groups.
PolyhedronParts boundary_parts(const Polyhedron& polyhedron);

/// Tags every boundary facet of `mesh` (a mesh of the polyhedron) with the part
/// of the surface triangle that contains the facet's centroid; throws
/// warpfem::Error if a facet lies on no triangle (the mesh does not fit the surface).
void tag_facets_by_part(Mesh<3>& mesh, const Polyhedron& polyhedron, const PolyhedronParts& parts);

}  // namespace warpfem::fem
