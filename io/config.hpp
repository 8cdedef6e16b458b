#pragma once
// The config of `warpfem run`: a Poisson config (io/run_config.hpp) or an
// elasticity config (io/elasticity_config.hpp), chosen by /problem/type, in 2D
// (a polygon source) or 3D (a polyhedron source, io/polyhedron_config.hpp).

#include <string>
#include <variant>

#include "io/elasticity_config.hpp"
#include "io/run_config.hpp"

namespace warpfem::io {

using Config = std::variant<RunConfig, ElasticityConfig, PoissonRunConfig<3>, ElasticityRunConfig<3>>;

/// Loads and validates the config at `path` (the file is read once); throws
/// warpfem::Error naming the file and field.
Config load_config(const std::string& path);

}  // namespace warpfem::io
