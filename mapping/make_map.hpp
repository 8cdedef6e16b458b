#pragma once
#include "mapping/map.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::mapping {

/// Builds the 2D map a spec describes; throws warpfem::Error naming
/// spec.origin and the offending field when the spec is inconsistent.
MapPtr<2> make_map(const MapSpec& spec);

}  // namespace warpfem::mapping
