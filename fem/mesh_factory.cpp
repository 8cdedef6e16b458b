#include "fem/mesh_factory.hpp"

#include "core/error.hpp"
#include "fem/gmsh_reader.hpp"
#include "fem/polygon_mesher.hpp"
#include "fem/structured_mesher.hpp"

namespace warpfem::fem {

Mesh<2> make_coarse_mesh(const Polygon& source, const MeshSpec& spec) {
  if (spec.type == "structured") return structured_mesh(source, spec.nx, spec.ny, spec.cell_type);
  if (spec.type == "gmsh") return read_gmsh(spec.file, source);
  if (spec.type != "delaunay" && spec.type != "quad_split")
    throw Error(
        "unknown mesh type \"" + spec.type + "\"",
        {.file = "", .key_path = "/mesh/type", .hint = "use delaunay, quad_split, structured or gmsh"});
  PolygonMeshOptions options;
  options.max_edge_length =
      spec.max_edge_length > 0 ? spec.max_edge_length : 0.1 * (source.bbox_max() - source.bbox_min()).norm();
  options.shape_bound = spec.shape_bound;
  Mesh<2> triangles = mesh_polygon(source, options);
  return spec.type == "quad_split" ? split_into_quadrilaterals(triangles) : triangles;
}

MeshHierarchy::MeshHierarchy(Mesh<2> coarse, int refinements) {
  levels.push_back(std::move(coarse));
  for (int r = 0; r < refinements; ++r) {
    transfers.push_back(refine_uniformly(levels.back()));
    levels.push_back(std::move(transfers.back().mesh));  // the parent maps stay in `transfers`
  }
}

}  // namespace warpfem::fem
