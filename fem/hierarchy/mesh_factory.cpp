#include "fem/hierarchy/mesh_factory.hpp"

#include <cmath>
#include <optional>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/gmsh_reader.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/tetgen_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/dofs/cell_partition.hpp"
#include "fem/hierarchy/partial_refinement.hpp"
#include "fem/hierarchy/polyhedron_parts.hpp"
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

// Extra vertices on the box's sides are allowed.
bool is_axis_aligned_box(const Polyhedron& p) {
  const Point<3> lo = p.bbox_min(), hi = p.bbox_max();
  const double tolerance = 1e-12 * (hi - lo).norm();
  for (const Point<3>& v : p.vertices()) {
    bool on_side = false;
    for (int d = 0; d < 3; ++d)
      on_side = on_side || std::abs(v(d) - lo(d)) <= tolerance || std::abs(v(d) - hi(d)) <= tolerance;
    if (!on_side) return false;
  }
  const double box = (hi - lo).prod();
  return std::abs(p.signed_volume() - box) <= 1e-9 * box;
}

Mesh<3> make_coarse_mesh(const Polyhedron& source, const Polyhedron&, const mapping::Map<3>&,
                         const MeshSpec& spec) {
  const PolyhedronParts parts = boundary_parts(source);
  if (spec.type == "structured") {
    if (!is_axis_aligned_box(source))  // io::parse_mesh_spec_for refuses this first
      throw Error(
          "mesh type \"structured\" grids a box, but " + source.name() + " is not an axis-aligned box",
          {.file = "",
           .key_path = "/mesh/type",
           .hint = "use \"type\": \"tetgen\" for other polyhedra, or give the box's surface"});
    Mesh<3> mesh = structured_box_mesh(source.bbox_min(), source.bbox_max(), {spec.nx, spec.ny, spec.nz},
                                       spec.cell_type);
    tag_facets_by_part(mesh, source, parts);
    return mesh;
  }
  if (spec.type == "gmsh") {
    GmshVolumeMesh read = read_gmsh(spec.file, source);
    const std::vector<int> physical = read.mesh.facet_tags;
    try {  // every boundary facet on the surface, also when the file names the parts
      tag_facets_by_part(read.mesh, source, parts);
    } catch (const Error& e) {
      throw Error(e.message(), {.file = spec.file, .key_path = "mesh.file", .hint = e.context().hint});
    }
    if (!read.physical_tags.empty()) {
      read.mesh.facet_tags = physical;
      std::string listing;
      for (std::size_t k = 0; k < read.physical_tags.size(); ++k)
        listing += (k ? ", " : "") + std::to_string(k) + " = physical " +
                   std::to_string(read.physical_tags[k]) +
                   (read.names[k].empty() ? "" : " \"" + read.names[k] + "\"");
      log::info("boundary parts (\"faces\") from the Gmsh file's physical groups: ", listing);
    }
    order_for_refinement(read.mesh);  // as for TetGen's meshes below
    return read.mesh;
  }
  if (spec.type != "tetgen")
    throw Error("mesh type \"" + spec.type + "\" does not mesh polyhedra",
                {.file = "", .key_path = "/mesh/type", .hint = "use \"tetgen\", \"structured\" or \"gmsh\""});
  TetrahedralMeshOptions options;
  options.quality_ratio = spec.quality_ratio;
  options.min_dihedral_angle = spec.min_dihedral_angle;
  options.max_volume = spec.max_volume;
  options.keep_surface = spec.keep_surface;
  options.triangle_tags = parts.triangle_part;
  // TetGen's vertex order is arbitrary; the refinements take the shortest
  // interior diagonal (a flat cell's children are as flat as the cell itself,
  // not flatter, and the multigrid counts stay bounded over levels).
  Mesh<3> mesh = mesh_polyhedron(source, options);
  order_for_refinement(mesh);
  return mesh;
}

}  // namespace warpfem::fem
