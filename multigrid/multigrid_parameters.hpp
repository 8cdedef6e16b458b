#pragma once
// The parameters of "solver.multigrid", bound to MultigridSettings (which holds the defaults).

#include "core/parameters.hpp"
#include "multigrid/pcmg.hpp"

namespace warpfem::multigrid {

const ParameterTable<MultigridSettings>& multigrid_parameters();

}  // namespace warpfem::multigrid
