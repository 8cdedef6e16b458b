#pragma once
// Reads meshes of Ω0 from Gmsh ASCII .msh files (format 2.2 and 4.1): 2D
// triangles or quadrilaterals of a polygon, 3D tetrahedra or hexahedra of a
// polyhedron. One parser serves both dimensions; every count in the file is
// checked against what follows it, so a damaged file is refused naming its line.

#include <string>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"
#include "core/polyhedron.hpp"

namespace warpfem {

/// Throws warpfem::Error naming the file and line for malformed input, mixed
/// cell types, or a mesh that does not cover `source` exactly. Only the 2D
/// cells are used; boundary facets are tagged with the source polygon's edges.
Mesh<2> read_gmsh(const std::string& path, const Polygon& source);

/// A 3D mesh from a Gmsh file, with the physical groups of its boundary.
struct GmshVolumeMesh {
  /// Positively oriented tetrahedra or hexahedra, outward boundary facets.
  /// facet_tags: part k for the k-th smallest physical tag of `physical_tags`,
  /// or -1 everywhere when the file puts no boundary triangle or quadrilateral
  /// in a physical group.
  Mesh<3> mesh;
  std::vector<int> physical_tags;  ///< sorted; the boundary parts' Gmsh physical tags
  std::vector<std::string> names;  ///< per part: its $PhysicalNames name, or ""
};

/// Reads tetrahedra (Gmsh type 4) or hexahedra (type 5) and the boundary
/// triangles (2) or quadrilaterals (3) of physical groups. Throws
/// warpfem::Error naming the file, the line or element and a fix for
/// malformed input, other 3D element types, mixed cells, inverted or
/// degenerate cells, a vertex of `source` missing from the mesh, a volume
/// different from the source's, or a boundary only partly in physical groups.
/// Whether the boundary facets lie on the surface is checked by the caller
/// that tags them (fem/hierarchy/polyhedron_parts.hpp).
GmshVolumeMesh read_gmsh(const std::string& path, const Polyhedron& source);

}  // namespace warpfem
