#include "io/config.hpp"

#include "io/config_node.hpp"
#include "io/polyhedron_config.hpp"

namespace warpfem::io {

Config load_config(const std::string& path) {
  const nlohmann::json json = ConfigNode::parse_file(path);
  const bool elasticity = problem_type(json, path) == "elasticity";
  if (is_polyhedron_map(json)) {
    if (elasticity) return parse_elasticity_config_for<3>(json, path);
    return parse_poisson_config<3>(json, path);
  }
  if (elasticity) return parse_elasticity_config(json, path);
  return parse_run_config(json, path);
}

}  // namespace warpfem::io
