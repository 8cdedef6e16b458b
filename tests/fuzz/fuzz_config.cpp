// libFuzzer target: a config file as `warpfem run` loads it — JSON syntax,
// duplicate keys, nesting, then every field of a Poisson or elasticity config
// with its range checks and the size estimates made before anything is built.

#include <cstddef>
#include <cstdint>

#include "fuzz_input.hpp"
#include "io/config_node.hpp"
#include "io/elasticity_config.hpp"
#include "io/run_config.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  warpfem::fuzz::start_environment();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace warpfem;
  const std::string path = fuzz::write_input("config.json", data, size);
  fuzz::refused_or_accepted([&] {
    const nlohmann::json json = io::ConfigNode::parse_file(path);
    if (io::problem_type(json, path) == "elasticity") {
      const io::ElasticityConfig cfg = io::parse_elasticity_config(json, path);
      io::make_elasticity_data(cfg);
    } else {
      const io::RunConfig cfg = io::parse_run_config(json, path);
      io::make_boundary_conditions(cfg.poisson.dirichlet, path);
    }
  });
  return 0;
}
