#pragma once
// Adaptive binary partition for a bijective composite map (thesis §4.5.3, Algorithm 1),
// followed by a check of the whole composite.
//
// 1. buildPartition(a, b): J_min ← min det J of the single step Ω_a → Ω_b on a dense
//    sample of Ω_a; if J_min ≤ 0 and b − a > ε, insert c = (a+b)/2 and recurse on
//    [a, c] and [c, b]. If J_min ≤ 0 and b − a ≤ ε we throw: never a folding map.
// 2. Composite check: a dense sample of Ω0 (grid plus points clustered toward every
//    vertex and edge) is pushed through all steps. Since det J_f = Π_k det J_k(x_k),
//    every step must stay positive along the pushed-forward points; steps that do
//    not are bisected (again bounded by ε) and the check repeats.
// The result carries a report explaining why the map is bijective (on the sample).

#include <memory>
#include <vector>

#include "mapping/composite_mean_value_map.hpp"
#include "mapping/distortion.hpp"
#include "mapping/vertex_path.hpp"

namespace warpfem::mapping {

struct AdaptiveOptions {
  int sample_resolution = 64;  ///< grid cells per bounding-box side for the det J samples
  Real min_interval = 1e-4;    ///< ε: intervals are not split below this length
  int max_rounds = 30;         ///< composite re-check rounds before giving up
  Coordinates coordinates = Coordinates::mean_value;
};

/// Why a composite map is bijective, in numbers.
struct CompositeReport {
  std::vector<Real> times;               ///< partition t_0 = 0 < … < t_m = 1
  std::vector<Real> step_min_det;        ///< per step: min det J_k on the sample of Ω_{t_k} (Algorithm 1)
  std::vector<Real> step_min_det_along;  ///< per step: min det J_k along the pushed-forward Ω0 sample
  Real composite_min_det = 0;            ///< min det J_f over the Ω0 sample
  DistortionSummary distortion;          ///< conformal / isometric distortion of f over the Ω0 sample
  Index samples = 0;                     ///< size of the Ω0 sample
  int rounds = 0;                        ///< composite checks performed (1 = first one passed)
  Index steps() const { return static_cast<Index>(times.size()) - 1; }
};

/// Algorithm 1 alone on [a, b]: returns the inner split points in increasing order
/// and appends the accepted intervals' min det J to `interval_min_det`. Throws
/// warpfem::Error naming the interval and the min det J when ε is reached.
std::vector<Real> binary_partition(const VertexPath& path, Real a, Real b, const AdaptiveOptions& options,
                                   std::vector<Real>* interval_min_det = nullptr);

struct AdaptiveComposite {
  std::shared_ptr<const CompositeMeanValueMap> map;
  CompositeReport report;
};

/// Algorithm 1 plus the composite check. Throws warpfem::Error if bijectivity
/// cannot be reached with intervals ≥ ε (message: the interval and min det J).
AdaptiveComposite build_adaptive_composite(const VertexPath& path, const AdaptiveOptions& options = {});

/// The composite check and distortion statistics of any composite (also
/// uniform/explicit ones) on the standard Ω0 sample; does not throw on folds.
CompositeReport analyze_composite(const CompositeMeanValueMap& map, int sample_resolution);

}  // namespace warpfem::mapping
