#pragma once
// The subcommands of the `warpfem` executable. Each takes the arguments after
// the subcommand name and returns the process exit code.

#include <string>
#include <vector>

namespace warpfem::apps {

int run_command(const std::vector<std::string>& args);
int study_command(const std::vector<std::string>& args);
int map_command(const std::vector<std::string>& args);
int warp_image_command(const std::vector<std::string>& args);

}  // namespace warpfem::apps
