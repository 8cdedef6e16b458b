// `warpfem run`: the one recipe every physics follows. The physics-specific
// parts (problem, solver, report, fields) are apps/physics.hpp strategies; the
// map, the mesh of Ω0 and the output are set up here, once.

#include "apps/run.hpp"

#include <iomanip>

#include "apps/command_line.hpp"
#include "apps/commands.hpp"
#include "apps/physics.hpp"
#include "apps/run_output.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/polyhedron_parts.hpp"
#include "io/config_field.hpp"
#include "mapping/make_map.hpp"

namespace warpfem::apps {
namespace {

std::string cell_plural(CellType type) {
  switch (type) {
    case CellType::tetrahedron: return "tetrahedra";
    case CellType::hexahedron: return "hexahedra";
    default: return warpfem::to_string(type) + "s";
  }
}

/// The boundary parts of a polyhedron source, which the config's "faces" name.
void log_boundary_parts(const Polyhedron& source) {
  const fem::PolyhedronParts parts = fem::boundary_parts(source);
  log::info("boundary parts (\"faces\") of ", source.name(), ": ", parts.count(),
            parts.given ? " given parts" : " planar face groups");
  for (int k = 0; k < parts.count(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    log::debug("  face ", k, ": normal (", parts.normal[i].transpose(), "), centroid (",
               parts.centroid[i].transpose(), ")");
  }
}

template <int dim, class Config>
RunResult run_recipe(const Config& cfg, MPI_Comm comm, const RunOptions& options) {
  RunResult result;
  Stopwatch total, watch;

  // 1. Config and options: `cfg` is validated (io::load_config); it names the physics.
  const std::unique_ptr<Physics<dim>> physics = make_physics(cfg, comm, options);

  // 2. The map f: Ω0 → Ω1, built and checked (a map that folds is refused here).
  const mapping::MapPtr<dim> map = [&] {
    if constexpr (dim == 2)
      return mapping::make_map(cfg.map, nullptr, comm);  // the ranks share the check and any interpolant
    else
      return mapping::make_map(cfg.map);
  }();
  log::info("map: ", map->describe(), " (", format_seconds(watch.seconds()), ")");

  // 3. The simple mesh of Ω0 (pulled back from Ω1 if the config asks); the physics
  // refines it into the hierarchy its solver needs.
  Mesh<dim> coarse = [&] {
    try {
      return fem::make_coarse_mesh(*cfg.map.source, cfg.map.target ? *cfg.map.target : *cfg.map.source, *map,
                                   cfg.mesh);
    } catch (const Error& e) {
      if (!e.context().key_path.empty()) throw;
      // A mesher's failure (TetGen's, say) names the surface; the mesh settings are what to change.
      throw Error(e.message(), {.file = cfg.file, .key_path = "/mesh", .hint = e.context().hint});
    }
  }();
  if constexpr (dim == 3)
    if (cfg.mesh.file_parts == 0) log_boundary_parts(*cfg.map.source);  // else the Gmsh file's groups

  // 4. The problem on the warped mesh: a fem::Problem<dim> on the finest level.
  const fem::Problem<dim>& problem = physics->set_up(std::move(coarse), cfg.mesh.refinements, map);
  const Mesh<dim>& mesh = problem.mesh();
  result.num_cells = mesh.num_cells();
  result.num_dofs = problem.components() * problem.dofs().num_dofs();
  result.h = mesh.max_edge_length();
  if (mesh.partial)  // stored only around this rank's cells: the largest over the ranks
    MPI_Allreduce(MPI_IN_PLACE, &result.h, 1, MPI_DOUBLE, MPI_MAX, comm);
  log::info("mesh of Ω0: ", mesh.num_cells(), " ", cell_plural(mesh.cell_type), ", ", mesh.num_vertices(),
            " vertices, h = ", std::setprecision(4), result.h, " (", cfg.mesh.refinements, " refinements)");

  // 5. Solve: linear (Krylov + geometric multigrid), quasi-static load stepping or
  // transient time stepping. A time series writes its steps as they converge.
  std::unique_ptr<RunOutput<dim>> output;
  if (options.write_output && cfg.output.vtk) {
    const int order = cfg.output.vtk_order > 0 ? cfg.output.vtk_order
                                               : std::max(physics->order(), map->is_affine() ? 1 : 2);
    output = std::make_unique<RunOutput<dim>>(
        comm, RunOutputSettings{cfg.output.directory, cfg.output.name, cfg.output.compression, order},
        *physics, problem, *map);
  }
  physics->solve(output.get(), result);

  // 6. Report: errors against an exact solution, energies, min det F.
  physics->report(result);
  physics->release_solver();

  // 7. Output through io: the solved state (a time series is written already).
  if (output) output->finish(physics->state(), result);
  log::info("total ", format_seconds(total.seconds()));
  return result;
}

}  // namespace

RunResult run(const io::Config& config, MPI_Comm comm, const RunOptions& options) {
  return std::visit(
      [&](const auto& cfg) { return run_recipe<std::decay_t<decltype(cfg)>::dim>(cfg, comm, options); },
      config);
}

int run_command(const std::vector<std::string>& args) {
  const ConfigArguments arguments = parse_config_arguments(
      args, "config file", "usage: warpfem run <config.json> [--output-dir DIR] [PETSc options]");
  const std::string& config_path = arguments.config;
  const std::string& output_dir = arguments.output_dir;
  io::Config config = io::load_config(config_path);
  std::visit(
      [&](auto& cfg) {
        if (!output_dir.empty()) cfg.output.directory = output_dir;
        log::set_level(log::parse_level(cfg.verbosity));
        Environment::insert_petsc_options(cfg.solver.petsc_options, config_path + ": /solver/petsc_options");
        log::info("warpfem run ", config_path, " on ", Environment::size(), " rank(s)");
        log::info(
            "output directory ", cfg.output.directory,
            output_dir.empty() ? " (a relative output.directory starts at the config's directory)" : "");
      },
      config);
  try {
    run(config, PETSC_COMM_WORLD);
  } catch (const Error& e) {
    throw io::in_config(e, config_path);  // errors that name a config field come from this config
  }
  return 0;
}

}  // namespace warpfem::apps
