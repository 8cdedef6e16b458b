#pragma once
// The parameters of the "map" section, bound to MapSpec (which holds the defaults).

#include "core/parameters.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::mapping {

const ParameterTable<MapSpec>& map_parameters();

}  // namespace warpfem::mapping
