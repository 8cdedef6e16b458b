#pragma once
// Command-line checks shared by the subcommands. PETSc options start with a
// single dash and pass through; an argument starting with "--" must be one of
// the subcommand's own flags, so that a typo such as --ouput-dir is refused
// instead of being taken for a PETSc option and ignored.

#include <string>
#include <vector>

namespace warpfem::apps {

/// Throws warpfem::Error if `arg` starts with "--" and is not in `flags`
/// (with a "did you mean" suggestion and `usage`).
void check_flag(const std::string& arg, const std::vector<std::string>& flags, const std::string& usage);

/// The arguments of `run` and `study`: a config file first, then an optional
/// `--output-dir DIR`; everything else must be a PETSc option (already read
/// by PetscInitialize). `what` names the config in the error for a missing one.
struct ConfigArguments {
  std::string config;
  std::string output_dir;  ///< "" if not given
};
ConfigArguments parse_config_arguments(const std::vector<std::string>& args, const std::string& what,
                                       const std::string& usage);

}  // namespace warpfem::apps
