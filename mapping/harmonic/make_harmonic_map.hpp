#pragma once
// Builds the composite harmonic map of a MapSpec (type "composite_harmonic"):
// harmonic_method, intermediate (regular | cyclic | optimized), boundary_nodes,
// fem_max_edge_length, distortion_energy and the per-edge speeds. An optimized Λ
// is searched with fem approximations (fast, the harmonic coordinates are
// solved once) and then used by the requested method.

#include "mapping/harmonic/composite_harmonic_map.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::mapping {

/// Throws warpfem::Error naming spec.origin and the offending parameter (field "map.<name>").
MapPtr<2> make_harmonic_map(const MapSpec& spec);

/// The same, with the concrete type (for reports and tests).
std::shared_ptr<const CompositeHarmonicMap> make_composite_harmonic(const MapSpec& spec);

}  // namespace warpfem::mapping
