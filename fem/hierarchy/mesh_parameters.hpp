#pragma once
// The parameters of the "mesh" section, bound to MeshSpec (which holds the defaults).

#include "core/parameters.hpp"
#include "fem/hierarchy/mesh_factory.hpp"

namespace warpfem::fem {

const ParameterTable<MeshSpec>& mesh_parameters();

}  // namespace warpfem::fem
