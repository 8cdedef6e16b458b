#pragma once
// The parameters of an elasticity run config, per section, bound to the structs
// of io/elasticity_config.hpp (which hold the defaults).

#include "core/parameters.hpp"
#include "io/elasticity_config.hpp"

namespace warpfem::io {

const ParameterTable<ElasticitySpec>& elasticity_parameters();
const ParameterTable<fem::Material>& material_parameters();
const ParameterTable<LoadSteppingSpec>& load_stepping_parameters();
const ParameterTable<TimeSpec>& time_parameters();
const ParameterTable<NewtonSpec>& newton_parameters();
const ParameterTable<ElasticityOutputSpec>& elasticity_output_parameters();

}  // namespace warpfem::io
