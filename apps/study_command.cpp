// warpfem study: convergence study of warped vs standard discretizations.

#include <petscsys.h>

#include "apps/command_line.hpp"
#include "apps/commands.hpp"
#include "apps/convergence_study.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/quadrature.hpp"
#include "io/config_field.hpp"
#include "io/polyhedron_config.hpp"

namespace warpfem::apps {

namespace {

template <int dim>
void run_study_config(io::PoissonRunConfig<dim> cfg, const StudySpec& spec, const nlohmann::json& json,
                      const std::string& path, const std::string& output_dir) {
  // The study integrates with the measurement rule (run_study), refines levels - 1
  // times more, and the reference solution further: sizes and the map's evaluation
  // follow that finest level.
  if (cfg.poisson.quadrature_degree == 0)
    cfg.poisson.quadrature_degree = measurement_quadrature_degree(cfg.poisson.order);
  const io::Discretization finest =
      io::poisson_discretization(cfg, cfg.mesh.refinements + spec.levels - 1 + spec.reference_levels);
  if constexpr (dim == 2) {
    io::check_discretization_size(io::ConfigNode(json, path), cfg.mesh, cfg.map, finest, cfg.limits,
                                  "/study/levels");
    cfg.map.evaluation_points =
        io::finest_quadrature_points(cfg.mesh, cfg.map, finest, cfg.poisson.quadrature_degree);
  } else {
    io::check_discretization_size(io::ConfigNode(json, path), cfg.mesh, *cfg.map.source, finest, cfg.limits,
                                  "/study/levels");
  }
  if (!output_dir.empty()) cfg.output.directory = output_dir;
  log::set_level(log::parse_level(cfg.verbosity));
  Environment::insert_petsc_options(cfg.solver.petsc_options, path + ": /solver/petsc_options");
  log::info("warpfem study ", path, ": ", spec.levels, " levels on ", Environment::size(), " rank(s)",
            dim == 3 ? " (polyhedra)" : "");
  try {
    run_study(cfg, spec, PETSC_COMM_WORLD);
  } catch (const Error& e) {
    throw io::in_config(e, path);  // errors that name a config field come from this config
  }
}

}  // namespace

int study_command(const std::vector<std::string>& args) {
  const ConfigArguments arguments = parse_config_arguments(
      args, "study config", "usage: warpfem study <study.json> [--output-dir DIR] [PETSc options]");
  const std::string& path = arguments.config;
  const std::string& output_dir = arguments.output_dir;
  nlohmann::json json = io::ConfigNode::parse_file(path);
  if (!json.is_object()) throw Error("expected a JSON object", {.file = path, .key_path = "/", .hint = ""});
  const nlohmann::json study_json = json.contains("study") ? json["study"] : nlohmann::json::object();
  json.erase("study");
  StudySpec spec = parse_study_spec(io::ConfigNode(study_json, path, "/study"));
  if (io::is_polyhedron_map(json))
    run_study_config(io::parse_poisson_config<3>(json, path), spec, json, path, output_dir);
  else
    run_study_config(io::parse_run_config(json, path), spec, json, path, output_dir);
  return 0;
}

}  // namespace warpfem::apps
