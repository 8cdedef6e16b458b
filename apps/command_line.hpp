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

}  // namespace warpfem::apps
