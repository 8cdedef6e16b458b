#include "io/run_config.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/log.hpp"
#include "core/mesh/gmsh_reader.hpp"
#include "fem/hierarchy/mesh_parameters.hpp"
#include "fem/hierarchy/polyhedron_parts.hpp"
#include "io/expression.hpp"
#include "io/parameter_reader.hpp"
#include "io/polyhedron_config.hpp"
#include "io/run_parameters.hpp"
#include "mapping/map_parameters.hpp"
#include "multigrid/multigrid_parameters.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

namespace {

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

/// Parses all of `token` as a finite double (from_chars: no locale, no
/// silent prefix parsing, and out-of-range values are reported, not clamped).
bool parse_finite(const std::string& token, double& value) {
  const char* begin = token.data() + (token.size() > 1 && token[0] == '+' && token[1] != '-' ? 1 : 0);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  return ec == std::errc() && ptr == end && std::isfinite(value);
}

/// Reads a polygon file: one vertex per line, "x,y" or "x y"; '#' starts a
/// comment. Every other non-blank line is an error naming the line.
std::vector<Point<2>> read_polygon_file(const std::string& path, const ConfigNode& node,
                                        const std::string& key) {
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw node.error(key, "polygon file \"" + path + "\" is a directory", "give the path of a text file");
  std::ifstream in(path);
  if (!in)
    throw node.error(key, "cannot open polygon file \"" + path + "\"",
                     "check the path (relative paths start at the config file's directory)");
  std::vector<Point<2>> pts;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::string text = line;
    if (auto hash = text.find('#'); hash != std::string::npos) text.erase(hash);
    for (char& ch : text)
      if (ch == ',' || ch == ';' || ch == '\t' || ch == '\r') ch = ' ';
    std::istringstream ls(text);
    std::vector<std::string> tokens;
    for (std::string t; ls >> t;) tokens.push_back(t);
    if (tokens.empty()) continue;  // blank or comment line
    double x = 0, y = 0;
    if (tokens.size() != 2 || !parse_finite(tokens[0], x) || !parse_finite(tokens[1], y))
      throw Error(
          "line " + std::to_string(number) + ": \"" + line +
              "\" is not a vertex: expected two finite numbers \"x, y\"",
          {.file = path, .key_path = "", .hint = "write one vertex per line; comments start with '#'"});
    pts.emplace_back(x, y);
  }
  if (in.bad())
    throw Error("cannot read the polygon file", {.file = path, .key_path = "", .hint = "check the file"});
  return pts;
}

}  // namespace

Polygon parse_polygon(const ConfigNode& node, const std::string& key, const std::string& name) {
  std::vector<Point<2>> pts;
  const nlohmann::json& raw = node.raw(key);
  std::string where = node.file();
  if (raw.is_string()) {
    fs::path p(raw.get<std::string>());
    if (p.is_relative()) p = fs::path(node.file()).parent_path() / p;
    pts = read_polygon_file(p.string(), node, key);
    where = p.string();
  } else {
    pts = node.get_points(key);
  }
  Polygon polygon(std::move(pts), name);
  try {
    polygon.validate();
  } catch (const Error& e) {
    throw Error(e.message(), {.file = where, .key_path = node.path_of(key), .hint = e.context().hint});
  }
  return polygon;
}

mapping::MapSpec parse_map_spec(const ConfigNode& node) {
  mapping::MapSpec spec;
  spec.origin = node.file();
  const auto& table = mapping::map_parameters();
  read_parameter(node, table, "type", spec);
  if (!node.has("source"))
    throw node.error("source", "missing required field: the source polygon Ω0 (an array of [x, y])",
                     "add \"source\": [[0,0], [1,0], [1,1], [0,1]]");
  spec.source = parse_polygon(node, "source", "source polygon");
  if (spec.type != "identity") {
    if (!node.has("target"))
      throw node.error("target",
                       "missing required field: the target polygon Ω1 for map type \"" + spec.type + "\"",
                       "add \"target\": [[x, y], ...] with as many vertices as the source");
    spec.target = parse_polygon(node, "target", "target polygon");
    try {
      require_same_vertex_count(*spec.source, *spec.target);
    } catch (const Error& e) {
      throw node.error("target", e.message(), e.context().hint);
    }
  } else if (node.has("target")) {
    throw node.error("target", "the identity map takes no target polygon",
                     "remove \"target\" or set \"type\": \"composite_mean_value\"");
  }
  read_parameters(node, table, spec);
  spec.times = node.get_doubles("times");
  for (const std::string key : {"source_edge_speeds", "target_edge_speeds"}) {
    if (!node.has(key)) continue;
    auto& out = key == "source_edge_speeds" ? spec.source_edge_speeds : spec.target_edge_speeds;
    const nlohmann::json& list = node.raw(key);
    if (!list.is_array())
      throw node.error(key, "expected an array of edge speeds, got " + json_excerpt(list));
    for (std::size_t i = 0; i < list.size(); ++i) {
      const auto& s = list[i];
      if (!s.is_string() || (s != "linear" && s != "quadratic" && s != "quadratic_reversed"))
        throw node.error(
            key + "/" + std::to_string(i),
            "expected \"linear\", \"quadratic\" or \"quadratic_reversed\", got " + json_excerpt(s));
      out.push_back(s.get<std::string>());
    }
    if (static_cast<Index>(out.size()) != spec.source->size())
      throw node.error(key, "expected one speed per edge (" + std::to_string(spec.source->size()) +
                                "), got " + std::to_string(out.size()));
  }
  if (spec.partition == "explicit" && spec.times.size() < 2)
    throw node.error("times", "partition \"explicit\" needs the list of times 0 = t0 < t1 < ... < tm = 1",
                     "add \"times\": [0, 0.5, 1]");
  node.finish();
  return spec;
}

template <int dim>
std::vector<int> parse_boundary_parts(const ConfigNode& item, Index num_parts) {
  const std::string key = boundary_part_key<dim>();
  const std::string other = boundary_part_key<5 - dim>();
  if (item.has(other))
    throw item.error(other,
                     dim == 2 ? "\"faces\" names faces of a polyhedron, but the source is a polygon"
                              : "\"edges\" names edges of a polygon, but the source is a polyhedron",
                     "rename \"" + other + "\" to \"" + key + "\"");
  const std::string what = dim == 2 ? "edge" : "face";
  const std::string hint = dim == 2 ? "edge i joins target vertices i and i+1"
                                    : "face i is part i of \"face_parts\" of the source polyhedron, or "
                                      "else its i-th planar face group, numbered by its first triangle "
                                      "(docs/config.md: boundary parts in 3D)";
  std::vector<int> parts;
  if (!item.has(key)) return parts;
  const nlohmann::json& e = item.raw(key);
  if (e.is_string() && e.get<std::string>() == "all") return parts;
  if (!e.is_array())
    throw item.error(key, "expected \"all\" or an array of " + what + " indices, got " + json_excerpt(e),
                     hint);
  if (e.empty())
    throw item.error(
        key, "an empty list selects no " + what + ", so this condition would do nothing",
        "list " + what + " indices, or omit the key (or use \"all\") to select all " + what + "s");
  for (std::size_t k = 0; k < e.size(); ++k) {
    if (!e[k].is_number_integer() || e[k].get<long>() < 0 || e[k].get<long>() >= num_parts)
      throw item.error(key + "/" + std::to_string(k),
                       "expected " + std::string(dim == 2 ? "an " : "a ") + what + " index in [0, " +
                           std::to_string(num_parts - 1) + "], got " + json_excerpt(e[k]),
                       hint);
    parts.push_back(e[k].get<int>());
  }
  return parts;
}

template std::vector<int> parse_boundary_parts<2>(const ConfigNode&, Index);
template std::vector<int> parse_boundary_parts<3>(const ConfigNode&, Index);

namespace {

template <int dim>
std::vector<BoundarySpec> parse_boundary(const ConfigNode& node, const std::string& key, Index num_parts) {
  std::vector<BoundarySpec> out;
  if (!node.has(key)) return out;
  const nlohmann::json& list = node.raw(key);
  const std::string parts_key = boundary_part_key<dim>();
  if (!list.is_array())
    throw node.error(key, "expected an array of {\"" + parts_key + "\": ..., \"value\": ...} objects, got " +
                              json_excerpt(list));
  for (std::size_t i = 0; i < list.size(); ++i) {
    const ConfigNode item(list[i], node.file(), node.path_of(key) + "/" + std::to_string(i));
    BoundarySpec bc;
    bc.key_path = item.path_of("value");
    bc.edges = parse_boundary_parts<dim>(item, num_parts);
    if (!item.has("value"))
      throw item.error(
          "value", "missing required field",
          dim == 2 ? "give a number or an expression of x, y" : "give a number or an expression of x, y, z");
    bc.value = item.get_expression("value", "0");
    Expression(bc.value, node.file(), bc.key_path);  // syntax check now
    item.finish();
    out.push_back(bc);
  }
  return out;
}

}  // namespace

MeshSpec parse_mesh_spec(const ConfigNode& mesh, int dim) {
  MeshSpec spec;
  const auto& table = fem::mesh_parameters();
  if (dim == 3) spec.type = "tetgen";
  read_parameters(mesh, table, spec);
  if (dim == 3 && spec.type != "tetgen" && spec.type != "structured" && spec.type != "gmsh")
    throw mesh.error("type",
                     "mesh type \"" + spec.type + "\" meshes polygons, but the source is a polyhedron",
                     "use \"tetgen\" (tetrahedra of any polyhedron), \"structured\" (a box) or \"gmsh\" (a "
                     ".msh file)");
  if (dim == 2 && spec.type == "tetgen")
    throw mesh.error("type", "TetGen meshes polyhedra, but the source is a polygon",
                     "use \"delaunay\", or give a polyhedron source {\"vertices\": ..., \"triangles\": ...}");
  for (const std::string key : {"quality_ratio", "min_dihedral_angle", "max_volume", "keep_surface"})
    if (mesh.has(key) && spec.type != "tetgen")
      throw mesh.error(key, "\"" + key + "\" is an option of mesh type \"tetgen\", not \"" + spec.type + "\"",
                       "remove \"" + key + "\"");
  // The default cell type follows the mesh type.
  const auto& cell_type = table.at("cell_type");
  if (spec.type == "structured")
    spec.cell_type = dim == 2 ? warpfem::CellType::quadrilateral : warpfem::CellType::hexahedron;
  if (spec.type == "tetgen" || (dim == 3 && spec.type == "gmsh"))
    spec.cell_type = warpfem::CellType::tetrahedron;
  cell_type.set(spec,
                mesh.get_choice("cell_type", std::get<std::string>(cell_type.get(spec)), cell_type.choices));
  const bool cell_3d =
      spec.cell_type == warpfem::CellType::tetrahedron || spec.cell_type == warpfem::CellType::hexahedron;
  if (dim == 3 && !cell_3d)
    throw mesh.error("cell_type",
                     "\"" + warpfem::to_string(spec.cell_type) +
                         "\" is a 2D cell, but the source is a polyhedron (a 3D config)",
                     "use \"tetrahedron\" or \"hexahedron\"");
  if (dim == 2 && cell_3d)
    throw mesh.error("cell_type",
                     "\"" + warpfem::to_string(spec.cell_type) +
                         "\" is a 3D cell, but the source is a polygon (a 2D config)",
                     "use \"triangle\" or \"quadrilateral\", or give a polyhedron source");
  if (spec.type == "tetgen" && spec.cell_type != warpfem::CellType::tetrahedron)
    throw mesh.error("cell_type", "TetGen meshes are made of tetrahedra",
                     "use \"type\": \"structured\" for hexahedra of a box");
  if (spec.type == "delaunay" && spec.cell_type != warpfem::CellType::triangle)
    throw mesh.error("cell_type", "delaunay meshes are made of triangles",
                     "use \"type\": \"quad_split\" for quadrilaterals");
  if (spec.type == "quad_split") spec.cell_type = warpfem::CellType::quadrilateral;
  if (mesh.has("cells")) {
    const nlohmann::json& c = mesh.raw("cells");
    const auto positive = [](const nlohmann::json& v) { return v.is_number_integer() && v.get<long>() >= 1; };
    if (positive(c)) {
      spec.nx = spec.ny = spec.nz = c.get<int>();
    } else if (c.is_array() && c.size() == static_cast<std::size_t>(dim) &&
               std::all_of(c.begin(), c.end(), positive)) {
      spec.nx = c[0].get<int>();
      spec.ny = c[1].get<int>();
      if (dim == 3) spec.nz = c[2].get<int>();
    } else {
      throw mesh.error("cells",
                       std::string("expected a positive integer or ") +
                           (dim == 2 ? "[nx, ny]" : "[nx, ny, nz]") + ", got " + json_excerpt(c),
                       dim == 2 ? "e.g. \"cells\": [4, 4]" : "e.g. \"cells\": [4, 4, 4]");
    }
  }
  if (spec.type == "tetgen" && spec.quality_ratio > 0 && spec.quality_ratio < 1.2)
    throw mesh.error("quality_ratio",
                     "a radius-edge ratio bound of " + number_text(spec.quality_ratio) +
                         " cannot be used: TetGen may not terminate below 1.2",
                     "use 0 (no quality bound) or a ratio of at least 1.2, e.g. 2");
  if (spec.type == "tetgen" && spec.min_dihedral_angle > 0 && spec.quality_ratio == 0)
    throw mesh.error("min_dihedral_angle", "a dihedral angle bound needs TetGen's quality refinement",
                     "give \"quality_ratio\" > 0 (e.g. 2) too, or remove \"min_dihedral_angle\"");
  if (spec.type == "gmsh") {
    if (spec.file.empty())
      throw mesh.error("file", "mesh type \"gmsh\" needs a .msh file", "add \"file\": \"domain.msh\"");
    if (fs::path(spec.file).is_relative())
      spec.file = (fs::path(mesh.file()).parent_path() / spec.file).string();
  }
  mesh.finish();
  return spec;
}

template <>
MeshSpec parse_mesh_spec_for<2>(const ConfigNode& mesh, const mapping::MapSpec&) {
  return parse_mesh_spec(mesh, 2);
}
template <>
MeshSpec parse_mesh_spec_for<3>(const ConfigNode& mesh, const mapping::PolyhedronMapSpec& map) {
  MeshSpec spec = parse_mesh_spec(mesh, 3);
  const Polyhedron& source = *map.source;
  if (spec.type == "gmsh") {
    // Read now, so that a bad file is refused before the map is built and "faces"
    // can be checked against the file's physical groups.
    GmshVolumeMesh read;
    try {
      read = read_gmsh(spec.file, source);
      fem::tag_facets_by_part(read.mesh, source, fem::boundary_parts(source));
    } catch (const Error& e) {
      throw Error(e.message(), {.file = e.context().file.empty() ? spec.file : e.context().file,
                                .key_path = mesh.path_of("file"),
                                .hint = e.context().hint});
    }
    if (mesh.has("cell_type") && spec.cell_type != read.mesh.cell_type)
      throw mesh.error("cell_type",
                       "\"" + warpfem::to_string(spec.cell_type) + "\" was asked for, but " +
                           fs::path(spec.file).filename().string() + " holds " +
                           warpfem::to_string(read.mesh.cell_type) + " cells",
                       "remove \"cell_type\" (a Gmsh file brings its cells)");
    spec.cell_type = read.mesh.cell_type;
    spec.file_cells = read.mesh.num_cells();
    spec.file_parts = static_cast<int>(read.physical_tags.size());
  }
  if (spec.type == "structured" && !fem::is_axis_aligned_box(source)) {
    const Point<3> lo = source.bbox_min(), hi = source.bbox_max();
    throw mesh.error("type",
                     "mesh type \"structured\" grids a box, but " + source.name() +
                         " is not an axis-aligned box (its volume is " + number_text(source.signed_volume()) +
                         ", its bounding box's " + number_text((hi - lo).prod()) + ")",
                     "use \"type\": \"tetgen\" for other polyhedra, or give the box's surface");
  }
  return spec;
}

std::string parse_verbosity(const ConfigNode& root) {
  RunConfig defaults;
  read_parameter(root, top_level_parameters(), "verbosity", defaults);
  return defaults.verbosity;
}

mapping::MapSpec parse_required_map(const ConfigNode& root) {
  if (!root.has("map"))
    throw root.error("map", "missing required field: the map (at least its source polygon)",
                     "add \"map\": {\"type\": \"identity\", \"source\": [[0,0],[1,0],[1,1],[0,1]]}");
  return parse_map_spec(root.child("map"));
}

void check_output_options(const ConfigNode& output, const std::string& name, int& vtk_order,
                          const std::string& cells, const std::string& example_name) {
  if (name.empty() || name.find('/') != std::string::npos)
    throw output.error("name", "expected a file name without '/', got \"" + name + "\"",
                       "use e.g. \"" + example_name + "\"");
  if (cells == "linear") {
    if (vtk_order > 1)
      throw output.error(
          "vtk_order",
          "\"cells\": \"linear\" writes straight cells through the vertices, but \"vtk_order\" "
          "asks for order " +
              std::to_string(vtk_order),
          "remove \"vtk_order\", or use \"cells\": \"curved\"");
    vtk_order = 1;
  }
}

std::string config_relative_path(const std::string& config_file, const std::string& path) {
  const fs::path p(path);
  if (p.empty() || p.is_absolute()) return path;
  return (fs::path(config_file).parent_path() / p).lexically_normal().string();
}

template <int dim>
PoissonRunConfig<dim> parse_poisson_config(const nlohmann::json& json, const std::string& file) {
  PoissonRunConfig<dim> cfg;
  cfg.file = file;
  const ConfigNode root(json, file);
  cfg.verbosity = parse_verbosity(root);
  cfg.map = parse_required_map_for<dim>(root);
  cfg.mesh = parse_mesh_spec_for<dim>(root.child("mesh"), cfg.map);
  const Index num_parts = boundary_part_count<dim>(cfg.map, cfg.mesh);

  const ConfigNode problem = root.child("problem");
  problem.get_choice("type", "poisson", {"poisson"});
  read_parameters(problem, poisson_parameters(), cfg.poisson);
  // One pass over the finest geometry (the assembly) streams; error norms against
  // an exact solution are a second pass, which the cache serves.
  if (cfg.poisson.geometry == "auto")
    cfg.poisson.geometry = cfg.poisson.exact_solution.empty() ? "streamed" : "cached";
  cfg.poisson.dirichlet = parse_boundary<dim>(problem, "dirichlet", num_parts);
  cfg.poisson.neumann = parse_boundary<dim>(problem, "neumann", num_parts);
  if (cfg.poisson.dirichlet.empty() && cfg.poisson.neumann.empty())
    throw problem.error(
        "dirichlet", "no boundary condition given",
        std::string("add \"dirichlet\": [{\"") + boundary_part_key<dim>() + "\": \"all\", \"value\": 0}]");
  if (cfg.poisson.dirichlet.empty())
    throw problem.error(
        "dirichlet",
        "only Neumann conditions: the solution is determined up to a constant, and solvable only "
        "if the source and the fluxes balance",
        dim == 2
            ? "prescribe the value on at least one edge, e.g. \"dirichlet\": [{\"edges\": [0], \"value\": 0}]"
            : "prescribe the value on at least one face, e.g. \"dirichlet\": [{\"faces\": [0], \"value\": "
              "0}]");
  problem.finish();

  const ConfigNode solver = root.child("solver");
  const auto& lin = cfg.solver.linear;
  read_parameters(solver, solver_parameters(), cfg.solver);
  if (solver.has("multigrid") && lin.pc_type != "mg")
    throw solver.error(
        "multigrid",
        "multigrid settings are given, but \"pc_type\" is \"" + lin.pc_type + "\", so they would be ignored",
        "remove \"multigrid\", or set \"pc_type\": \"mg\" (the default)");
  {
    using S = multigrid::MultigridSettings;
    const ConfigNode mg = solver.child("multigrid");
    S& m = cfg.solver.multigrid;
    read_parameters(mg, multigrid::multigrid_parameters(), m);
    if (m.prolongation == S::Prolongation::smoothed && mg.has("coarse_operators") &&
        m.coarse_operators == S::CoarseOperators::rediscretization)
      throw mg.error("coarse_operators",
                     "smoothed prolongations come with Galerkin operators, not rediscretized ones",
                     "remove \"coarse_operators\", or use \"prolongation\": \"geometric\"");
    if (m.chebyshev_bounds == S::ChebyshevBounds::gershgorin &&
        ((m.smoother != S::Smoother::chebyshev_jacobi && m.smoother != S::Smoother::automatic) ||
         m.coarse_operators == S::CoarseOperators::galerkin || m.prolongation == S::Prolongation::smoothed))
      throw mg.error("chebyshev_bounds",
                     "\"gershgorin\" bounds the Jacobi-preconditioned operator of rediscretized levels only",
                     "use \"auto\" or \"estimate\", or the smoother \"chebyshev_jacobi\" with "
                     "\"coarse_operators\": \"rediscretization\"");
    if (m.chebyshev_bounds == S::ChebyshevBounds::ssor && m.smoother != S::Smoother::chebyshev_sor)
      throw mg.error("chebyshev_bounds", "\"ssor\" bounds the SOR-preconditioned operator only",
                     "add \"smoother\": \"chebyshev_sor\", or use \"auto\" or \"estimate\"");
    mg.finish();
  }
  solver.finish();

  const ConfigNode output = root.child("output");
  read_parameters(output, output_parameters(), cfg.output);
  check_output_options(output, cfg.output.name, cfg.output.vtk_order, cfg.output.cells, "solution");
  cfg.output.directory = config_relative_path(file, cfg.output.directory);
  output.finish();
  cfg.limits = parse_limits(root);
  root.finish();
  const Discretization discretization = poisson_discretization(cfg, cfg.mesh.refinements);
  check_run_size<dim>(root, cfg.mesh, cfg.map, discretization, cfg.limits);
  if constexpr (dim == 2)
    cfg.map.evaluation_points =
        finest_quadrature_points(cfg.mesh, cfg.map, discretization, cfg.poisson.quadrature_degree);
  return cfg;
}

template PoissonRunConfig<2> parse_poisson_config<2>(const nlohmann::json&, const std::string&);
template PoissonRunConfig<3> parse_poisson_config<3>(const nlohmann::json&, const std::string&);

RunConfig parse_run_config(const nlohmann::json& json, const std::string& file) {
  return parse_poisson_config<2>(json, file);
}

template <>
mapping::MapSpec parse_required_map_for<2>(const ConfigNode& root) {
  return parse_required_map(root);
}
template <>
mapping::PolyhedronMapSpec parse_required_map_for<3>(const ConfigNode& root) {
  return parse_polyhedron_map_spec(root.child("map"));
}

template <>
Index boundary_part_count<2>(const mapping::MapSpec& map, const MeshSpec&) {
  return map.source->size();
}
template <>
Index boundary_part_count<3>(const mapping::PolyhedronMapSpec& map, const MeshSpec& mesh) {
  return mesh.file_parts > 0 ? mesh.file_parts : fem::boundary_parts(*map.source).count();
}

template <>
void check_run_size<2>(const ConfigNode& root, const MeshSpec& mesh, const mapping::MapSpec& map,
                       const Discretization& d, const SizeLimits& limits) {
  check_map_size(root, map, limits);
  check_discretization_size(root, mesh, map, d, limits);
}
template <>
void check_run_size<3>(const ConfigNode& root, const MeshSpec& mesh, const mapping::PolyhedronMapSpec& map,
                       const Discretization& d, const SizeLimits& limits) {
  check_discretization_size(root, mesh, *map.source, d, limits);
}

template <int dim>
Discretization poisson_discretization(const PoissonRunConfig<dim>& cfg, int refinements) {
  return {.refinements = refinements,
          .order = cfg.poisson.order,
          .components = 1,
          .cached_bytes_per_cell = cfg.poisson.geometry == "cached"
                                       ? cached_geometry_bytes_per_cell(cfg.mesh.cell_type, cfg.poisson.order,
                                                                        cfg.poisson.quadrature_degree)
                                       : 0.0};
}

template Discretization poisson_discretization(const PoissonRunConfig<2>&, int);
template Discretization poisson_discretization(const PoissonRunConfig<3>&, int);

RunConfig load_run_config(const std::string& path) {
  const nlohmann::json json = ConfigNode::parse_file(path);
  return parse_run_config(json, path);
}

template <int dim>
fem::ScalarFunction<dim> expression_function(const std::string& text, const std::string& file,
                                             const std::string& key_path) {
  const Expression e(text, file, key_path);
  if (e.is_constant()) return fem::ConstantFunction{e(0.0, 0.0)};  // recognisable, no parser per point
  auto copy = std::make_shared<Expression>(e);
  return [copy](const Point<dim>& x, double t) { return copy->at<dim>(x, t); };
}

template <int dim>
std::vector<fem::BoundaryCondition<dim>> make_boundary_conditions(const std::vector<BoundarySpec>& specs,
                                                                  const std::string& file) {
  std::vector<fem::BoundaryCondition<dim>> out;
  for (const auto& s : specs) out.push_back({s.edges, expression_function<dim>(s.value, file, s.key_path)});
  return out;
}

template fem::ScalarFunction<2> expression_function<2>(const std::string&, const std::string&,
                                                       const std::string&);
template fem::ScalarFunction<3> expression_function<3>(const std::string&, const std::string&,
                                                       const std::string&);
template std::vector<fem::BoundaryCondition<2>> make_boundary_conditions<2>(const std::vector<BoundarySpec>&,
                                                                            const std::string&);
template std::vector<fem::BoundaryCondition<3>> make_boundary_conditions<3>(const std::vector<BoundarySpec>&,
                                                                            const std::string&);

}  // namespace warpfem::io
