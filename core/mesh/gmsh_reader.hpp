#pragma once
// Reads 2D triangle or quadrilateral meshes of Ω0 from Gmsh ASCII .msh files
// (format 2.2 and 4.1). Only the 2D cells are used; boundary facets are
// recomputed and tagged with the source polygon's edges.

#include <string>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"

namespace warpfem {

/// Throws warpfem::Error naming the file and line for malformed input, mixed
/// cell types, or a mesh that does not cover `source` exactly.
Mesh<2> read_gmsh(const std::string& path, const Polygon& source);

}  // namespace warpfem
