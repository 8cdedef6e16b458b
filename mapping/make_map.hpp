#pragma once
#include "mapping/map.hpp"
#include "mapping/map_check.hpp"
#include "mapping/map_spec.hpp"
#include "mapping/polyhedron_map_check.hpp"

namespace warpfem::mapping {

/// Builds the 2D map a spec describes and runs the fold check (map_check.hpp)
/// on it: a map with det J_f ≤ 0, a non-finite value or a failed inverse on
/// the check sample is never returned. Throws warpfem::Error naming
/// spec.origin and the offending field when the spec is inconsistent or the
/// map is refused. With spec.certify, a mean value map must also pass the
/// certificate (mean_value_certificate.hpp), which is logged and stored in
/// check->certificate; other maps log that they are not certified.
/// `check`, if given, receives the check's numbers. Collective over `comm`:
/// the ranks share the check and the build of a map interpolant, and all
/// return the same map (an error on any rank is thrown on every rank).
MapPtr<2> make_map(const MapSpec& spec, MapCheck* check = nullptr, MPI_Comm comm = MPI_COMM_SELF);

/// The same for polyhedra: the map is refused (an error naming spec.origin,
/// the field, the interval or the worst sample point, and a fix) unless its
/// check passes (polyhedron_map_check.hpp).
MapPtr<3> make_map(const PolyhedronMapSpec& spec, PolyhedronMapCheck* check = nullptr);

}  // namespace warpfem::mapping
