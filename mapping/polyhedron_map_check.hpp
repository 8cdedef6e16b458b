#pragma once
// The check every map between polyhedra passes before anyone uses it: on a
// sample of Ω0 clustered at every vertex, edge and face
// (polyhedron_check_sample), det J_f > 0 and finite, every image inside the
// target polyhedron, and the Newton inverse returning each sample point.
// Like the 2D check it is sampled, not a proof.

#include <functional>
#include <string>

#include "core/polyhedron.hpp"
#include "core/types.hpp"
#include "mapping/map.hpp"
#include "mapping/polyhedron_composite_map.hpp"

namespace warpfem::mapping {

struct PolyhedronMapCheck {
  Index samples = 0;
  Index nonpositive = 0;  ///< samples with det J_f ≤ 0 or not finite
  Index outside = 0;      ///< samples whose image lies outside the target
  Index failed_inverse = 0;
  Real min_det = 0;
  Point<3> min_det_at = Point<3>::Zero();
  Real max_round_trip = 0;  ///< largest |f⁻¹(f(x)) − x| relative to the source's size
  Point<3> worst_inverse_at = Point<3>::Zero();

  bool passed() const { return samples > 0 && nonpositive == 0 && outside == 0 && failed_inverse == 0; }
  std::string summary() const;
};

/// Runs the check of `f` between `source` and `target`.
PolyhedronMapCheck check_polyhedron_map(const PolyhedronCompositeMap& f, const Polyhedron& source,
                                        const Polyhedron& target, int per_feature = 3);

/// x = f⁻¹(y) with a residual per point (the maps' own inverse).
using PolyhedronMapInverse = std::function<void(const Points<3>& y, Points<3>& x, VectorX& residual)>;

/// The same check for any map between polyhedra with its inverse.
PolyhedronMapCheck check_polyhedron_map(const Map<3>& f, const PolyhedronMapInverse& inverse,
                                        const Polyhedron& source, const Polyhedron& target,
                                        int per_feature = 3);

}  // namespace warpfem::mapping
