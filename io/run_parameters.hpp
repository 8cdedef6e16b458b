#pragma once
// The parameters of a Poisson run config, per section, bound to the structs of
// io/run_config.hpp (which hold the defaults). The "map", "mesh" and
// "solver.multigrid" sections have their tables in their modules.

#include "core/parameters.hpp"
#include "io/run_config.hpp"

namespace warpfem::io {

const ParameterTable<RunConfig>& top_level_parameters();
const ParameterTable<PoissonSpec>& poisson_parameters();
const ParameterTable<SolverSpec>& solver_parameters();
const ParameterTable<OutputSpec>& output_parameters();
const ParameterTable<SizeLimits>& limits_parameters();

}  // namespace warpfem::io
