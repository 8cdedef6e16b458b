#pragma once
// The fold check every built map passes before anyone uses it: f and J_f are
// evaluated together at the points of bijectivity_sample() (a grid plus points
// clustered at every vertex and edge), and the map is refused when any sample
// has det J_f ≤ 0, a value that is not finite, or a failed inverse (residual
// above the map's inverse_tolerance()). It is a sampled check, not a proof.

#include <mpi.h>

#include <optional>
#include <string>

#include "core/types.hpp"
#include "mapping/map.hpp"
#include "mapping/map_spec.hpp"
#include "mapping/mean_value_certificate.hpp"

namespace warpfem::mapping {

struct MapCheck {
  Index samples = 0;
  Index nonpositive = 0;     ///< samples with det J_f ≤ 0
  Index not_finite = 0;      ///< samples where f or J_f is NaN or infinite
  Index failed_inverse = 0;  ///< samples whose inverse residual exceeds the tolerance
  Real min_det = 0;          ///< smallest finite det J_f
  Point<2> min_det_at = Point<2>::Zero();
  Real max_residual = 0;  ///< largest inverse residual (NaN counts as failed, not here)
  Point<2> max_residual_at = Point<2>::Zero();
  Real inverse_tolerance = 0;
  Point<2> first_not_finite_at = Point<2>::Zero();
  Real build_seconds = 0;  ///< building the map and running this check (make_map)
  /// The proven lower bound of det J_f, when MapSpec::certify asked for one
  /// and the map is a mean value map.
  std::optional<MapCertificate> certificate;

  bool passed() const { return samples > 0 && nonpositive == 0 && not_finite == 0 && failed_inverse == 0; }
  /// "min det J_f = …, … samples, max inverse residual …" for logs.
  std::string summary() const;
};

/// Evaluates f with its Jacobians and inverse residuals at `sample` (points of Ω0).
MapCheck check_map(const Map<2>& f, const Points<2>& sample);

/// The same, collective over `comm`: each rank checks a share of the sample,
/// every rank receives the result the whole sample gives on one rank (an
/// evaluation failing on any rank throws on every rank).
MapCheck check_map(const Map<2>& f, const Points<2>& sample, MPI_Comm comm);

/// The check on bijectivity_sample(source, spec.sample_resolution), collective over `comm`.
MapCheck check_map(const Map<2>& f, const MapSpec& spec, MPI_Comm comm = MPI_COMM_SELF);

/// Throws warpfem::Error naming spec.origin unless the check passed: how many
/// samples fail and why, the worst location, and a fix for the map type.
void require_passed(const MapCheck& check, const MapSpec& spec);

}  // namespace warpfem::mapping
