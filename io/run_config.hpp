#pragma once
// The configuration of one `warpfem run`: geometry and map, mesh of Ω0,
// physics, solver and output. See docs/config.md for every field and default.

#include <string>
#include <vector>

#include "core/petsc/linear_solve.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/physics/functions.hpp"
#include "io/config_node.hpp"
#include "io/size_limits.hpp"
#include "mapping/map_spec.hpp"
#include "multigrid/pcmg.hpp"

namespace warpfem::io {

using MeshSpec = fem::MeshSpec;

/// What describes Ω0 and the map in `dim` dimensions: polygons or polyhedra.
template <int dim>
struct MapSpecOfDim;
template <>
struct MapSpecOfDim<2> {
  using type = mapping::MapSpec;
};
template <>
struct MapSpecOfDim<3> {
  using type = mapping::PolyhedronMapSpec;
};
template <int dim>
using MapSpecFor = typename MapSpecOfDim<dim>::type;

/// A condition on boundary parts: source polygon edges in 2D ("edges"), boundary
/// parts of the source polyhedron in 3D ("faces", fem/hierarchy/polyhedron_parts.hpp).
struct BoundarySpec {
  std::vector<int> edges;  ///< the parts; empty: all
  std::string value;       ///< expression of x, y (, z) (physical coordinates), t
  std::string key_path;    ///< for error messages
};

struct PoissonSpec {
  int order = 1;              ///< Lagrange order (1 or 2)
  int quadrature_degree = 0;  ///< 0: warpfem::default_quadrature_degree(order)
  std::string source = "0";   ///< g in −Δu = g
  std::vector<BoundarySpec> dirichlet;
  std::vector<BoundarySpec> neumann;  ///< ∂u/∂n = h (outward normal)
  std::string exact_solution;         ///< optional: report L2/H1 errors against it
  std::string geometry = "auto";      ///< cached | streamed (fem::GeometryStorage); auto: resolved when read
};

struct SolverSpec {
  /// Geometric multigrid on the nested hierarchy by default.
  petsc::LinearSolveOptions linear = [] {
    petsc::LinearSolveOptions o;
    o.pc_type = "mg";
    return o;
  }();
  multigrid::MultigridSettings multigrid;  ///< "multigrid": smoother, cycle, coarse operators, steps
  std::string petsc_options;               ///< extra PETSc options, e.g. "-ksp_monitor"
};

struct OutputSpec {
  std::string directory = "output";
  std::string name = "solution";
  bool vtk = true;
  int vtk_order = 0;                 ///< 0: 2 for warped geometry (curved cells), else the element order
  std::string compression = "none";  ///< none | lz4 | zlib (VTK's data compressor)
  std::string cells = "curved";      ///< curved | linear (linear: vertices only, vtk_order 1)
};

/// A Poisson run on a polygon (dim 2) or a polyhedron (dim 3).
template <int dim_>
struct PoissonRunConfig {
  static constexpr int dim = dim_;
  std::string file;
  std::string verbosity = "info";
  MapSpecFor<dim> map;
  MeshSpec mesh;
  PoissonSpec poisson;
  SolverSpec solver;
  OutputSpec output;
  SizeLimits limits;  ///< "limits": memory and file caps of the size checks
};
using RunConfig = PoissonRunConfig<2>;

/// What the size checks count for `cfg` refined `refinements` times.
template <int dim>
Discretization poisson_discretization(const PoissonRunConfig<dim>& cfg, int refinements);

/// Loads and validates a 2D run config; throws warpfem::Error naming the file and field.
RunConfig load_run_config(const std::string& path);
/// Same, from already parsed JSON (for tests); `file` is used in messages and to resolve relative paths.
RunConfig parse_run_config(const nlohmann::json& json, const std::string& file);
/// A Poisson config of either dimension (3 when the map's source is a polyhedron).
template <int dim>
PoissonRunConfig<dim> parse_poisson_config(const nlohmann::json& json, const std::string& file);

/// The top-level "map" of a `dim`-dimensional config (polygons or polyhedra).
template <int dim>
MapSpecFor<dim> parse_required_map_for(const ConfigNode& root);
// The specializations are declared here so that no caller instantiates the primary template first.
template <>
MapSpecFor<2> parse_required_map_for<2>(const ConfigNode& root);
template <>
MapSpecFor<3> parse_required_map_for<3>(const ConfigNode& root);

/// Number of boundary parts "edges" or "faces" name: the source polygon's edges, or
/// the source polyhedron's parts (a 3D Gmsh file's physical groups, if it has them).
template <int dim>
Index boundary_part_count(const MapSpecFor<dim>& map, const MeshSpec& mesh);
template <>
Index boundary_part_count<2>(const MapSpecFor<2>& map, const MeshSpec& mesh);
template <>
Index boundary_part_count<3>(const MapSpecFor<3>& map, const MeshSpec& mesh);

/// The config key that lists boundary parts: "edges" in 2D, "faces" in 3D.
template <int dim>
const char* boundary_part_key() {
  return dim == 2 ? "edges" : "faces";
}

/// The list of parts of a boundary condition item (`item` is its JSON object):
/// empty when the key is absent or "all". Errors name the item and say what a part is.
template <int dim>
std::vector<int> parse_boundary_parts(const ConfigNode& item, Index num_parts);

/// Size checks of a `dim`-dimensional discretization (io/size_limits.hpp).
template <int dim>
void check_run_size(const ConfigNode& root, const MeshSpec& mesh, const MapSpecFor<dim>& map,
                    const Discretization& d, const SizeLimits& limits);
template <>
void check_run_size<2>(const ConfigNode& root, const MeshSpec& mesh, const MapSpecFor<2>& map,
                       const Discretization& d, const SizeLimits& limits);
template <>
void check_run_size<3>(const ConfigNode& root, const MeshSpec& mesh, const MapSpecFor<3>& map,
                       const Discretization& d, const SizeLimits& limits);

/// Reads a polygon stored at `key`: an inline array of [x, y] or the name of a
/// file with one "x, y" per line (relative to the config file); validates it.
Polygon parse_polygon(const ConfigNode& node, const std::string& key, const std::string& name);

/// Reads the "map" object (shared by `run`, `map` and `warp-image` configs).
mapping::MapSpec parse_map_spec(const ConfigNode& node);

/// The top-level "verbosity" (quiet | error | warning | info | debug; default info).
std::string parse_verbosity(const ConfigNode& root);

/// The required top-level "map" object, with a helpful error when it is missing.
mapping::MapSpec parse_required_map(const ConfigNode& root);

/// Reads the "mesh" object (shared by all run configs) of a `dim`-dimensional config
/// (a polygon or a polyhedron source); refuses the mesh types and cell types of the other dimension.
MeshSpec parse_mesh_spec(const ConfigNode& node, int dim = 2);

/// The "mesh" object of a `dim`-dimensional config, checked against the map's
/// source before anything is built (3D "structured" needs a box source).
template <int dim>
MeshSpec parse_mesh_spec_for(const ConfigNode& node, const MapSpecFor<dim>& map);

/// Checks the "name", "vtk_order" and "cells" an "output" object gave (shared by
/// `run` and elasticity configs); "cells": "linear" sets `vtk_order` to 1.
void check_output_options(const ConfigNode& output, const std::string& name, int& vtk_order,
                          const std::string& cells, const std::string& example_name);

/// A path a config names, relative to the config file's directory unless it is absolute
/// (so that a run started from another directory reads and writes next to its config).
std::string config_relative_path(const std::string& config_file, const std::string& path);

/// An expression of x, y (, z), t as a function on points of dimension `dim`.
template <int dim>
fem::ScalarFunction<dim> expression_function(const std::string& text, const std::string& file,
                                             const std::string& key_path);

/// Turns boundary specs into fem boundary conditions (parses the expressions).
template <int dim = 2>
std::vector<fem::BoundaryCondition<dim>> make_boundary_conditions(const std::vector<BoundarySpec>& specs,
                                                                  const std::string& file);

}  // namespace warpfem::io
