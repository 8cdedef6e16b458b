#include <petscsys.h>

#include "apps/command_line.hpp"
#include "apps/commands.hpp"
#include "apps/elasticity_run.hpp"
#include "apps/poisson_run.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "io/config_field.hpp"

namespace warpfem::apps {

int run_command(const std::vector<std::string>& args) {
  const char* usage = "usage: warpfem run <config.json> [--output-dir DIR] [PETSc options]";
  if (args.empty() || args[0].rfind("-", 0) == 0)
    throw Error("missing config file (it must be the first argument)",
                {.file = "", .key_path = "", .hint = usage});
  const std::string config_path = args[0];
  std::string output_dir;
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--output-dir") {
      if (i + 1 >= args.size())
        throw Error("--output-dir needs a directory", {.file = "", .key_path = "", .hint = usage});
      output_dir = args[++i];
    } else {
      // Everything else is a PETSc option, already read by PetscInitialize.
      check_flag(args[i], {"--output-dir"}, usage);
    }
  }
  if (io::problem_type(io::ConfigNode::parse_file(config_path), config_path) == "elasticity")
    return run_elasticity_command(config_path, output_dir);
  io::RunConfig cfg = io::load_run_config(config_path);
  if (!output_dir.empty()) cfg.output.directory = output_dir;
  log::set_level(log::parse_level(cfg.verbosity));
  Environment::insert_petsc_options(cfg.solver.petsc_options, config_path + ": /solver/petsc_options");
  log::info("warpfem run ", config_path, " on ", Environment::size(), " rank(s)");
  log::info("output directory ", cfg.output.directory,
            output_dir.empty() ? " (a relative output.directory starts at the config's directory)" : "");
  try {
    run_poisson(cfg, PETSC_COMM_WORLD);
  } catch (const Error& e) {
    throw io::in_config(e, config_path);  // errors that name a config field come from this config
  }
  return 0;
}

}  // namespace warpfem::apps
