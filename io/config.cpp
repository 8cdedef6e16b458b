#include "io/config.hpp"

#include "io/config_node.hpp"

namespace warpfem::io {

Config load_config(const std::string& path) {
  const nlohmann::json json = ConfigNode::parse_file(path);
  if (problem_type(json, path) == "elasticity") return parse_elasticity_config(json, path);
  return parse_run_config(json, path);
}

}  // namespace warpfem::io
