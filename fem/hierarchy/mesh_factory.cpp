#include "fem/hierarchy/mesh_factory.hpp"

#include <optional>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/gmsh_reader.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "fem/dofs/cell_partition.hpp"
#include "fem/hierarchy/partial_refinement.hpp"
#include "fem/hierarchy/pullback_mesher.hpp"

namespace warpfem::fem {

namespace {
PolygonMeshOptions delaunay_options(const Polygon& meshed, const MeshSpec& spec) {
  PolygonMeshOptions options;
  options.max_edge_length =
      spec.max_edge_length > 0 ? spec.max_edge_length : 0.1 * (meshed.bbox_max() - meshed.bbox_min()).norm();
  options.shape_bound = spec.shape_bound;
  return options;
}
}  // namespace

Mesh<2> make_coarse_mesh(const Polygon& source, const MeshSpec& spec) {
  if (spec.type == "structured") return structured_mesh(source, spec.nx, spec.ny, spec.cell_type);
  if (spec.type == "gmsh") return read_gmsh(spec.file, source);
  if (spec.type == "pullback")
    throw Error(
        "mesh type \"pullback\" needs the map (it meshes the target polygon and pulls the mesh back)",
        {.file = "", .key_path = "mesh.type", .hint = "call make_coarse_mesh with the map and its target"});
  if (spec.type != "delaunay" && spec.type != "quad_split")
    throw Error("unknown mesh type \"" + spec.type + "\"",
                {.file = "",
                 .key_path = "mesh.type",
                 .hint = "use delaunay, quad_split, structured, gmsh or pullback"});
  Mesh<2> triangles = mesh_polygon(source, delaunay_options(source, spec));
  return spec.type == "quad_split" ? split_into_quadrilaterals(triangles) : triangles;
}

Mesh<2> make_coarse_mesh(const Polygon& source, const Polygon& target, const mapping::Map<2>& map,
                         const MeshSpec& spec) {
  if (spec.type != "pullback") return make_coarse_mesh(source, spec);
  PullbackReport report;
  Mesh<2> triangles = pull_back_target_mesh(source, target, map, delaunay_options(target, spec), &report);
  log::info("pulled the target's Delaunay mesh back to Ω0: ", triangles.num_cells(), " triangles, ",
            report.fold_repairs, " fold repairs, Newton residual ", report.max_residual,
            ", smallest/mean cell area in Ω0 ", report.min_area_ratio, ", largest cell distortion ",
            report.max_distortion);
  return spec.cell_type == CellType::quadrilateral ? split_into_quadrilaterals(triangles) : triangles;
}

}  // namespace warpfem::fem
