#pragma once
// `warpfem map` on a config whose map is between polyhedra.

#include <nlohmann/json.hpp>
#include <string>

namespace warpfem::apps {

/// Builds and checks the map, maps the points of `points_in` (if any) into
/// `points_out` and writes the warped tetrahedral grid of the source; returns
/// the exit code. Errors throw before anything is written.
int polyhedron_map_command(const nlohmann::json& config, const std::string& config_path,
                           const std::string& points_in, const std::string& points_out,
                           const std::string& output_dir);

}  // namespace warpfem::apps
