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
//
// Strategy `greedy` replaces step 1 by the longest steps that stay safely
// bijective: from t, the end b of the next step is the largest (found by
// bisection) with min det J of Ω_t → Ω_b at least `greedy_min_det`. Its cuts
// are not dyadic, so it usually needs fewer steps than Algorithm 1 (40-vertex
// gear: 5 instead of 7) and every map evaluation costs proportionally less.
// Step 2 (the composite check) is the same for both.
//
// Both refuse a pair whose partition would need more than max_steps steps: ε
// alone bounds a partition by ~1/ε steps, each checked on the full sample, and
// on extremely distorted pairs that took minutes. max_work() is the bound.

#include <memory>
#include <vector>

#include "mapping/composite_mean_value_map.hpp"
#include "mapping/distortion.hpp"
#include "mapping/vertex_path.hpp"

namespace warpfem::mapping {

enum class PartitionStrategy {
  binary,  ///< Algorithm 1: halve every folding interval
  greedy   ///< longest steps with min det J >= greedy_min_det (fewer steps)
};

/// What building a partition cost, in sample points pushed through one step
/// (the unit of work of every det J check).
struct PartitionWork {
  Index step_checks = 0;        ///< det J checks of one step on its own sample (Algorithm 1, greedy)
  Index point_evaluations = 0;  ///< sample points × steps evaluated, both phases together
  Index composite_rounds = 0;   ///< composite checks (phase 2)
};

struct AdaptiveOptions {
  int sample_resolution = 64;  ///< grid cells per bounding-box side for the det J samples
  Real min_interval = 1e-4;    ///< ε: intervals are not split below this length
  int max_rounds = 30;         ///< composite re-check rounds before giving up
  Coordinates coordinates = Coordinates::mean_value;
  PartitionStrategy strategy = PartitionStrategy::binary;
  Real greedy_min_det = 0.2;  ///< greedy: required min det J of every step on its sample
  /// Most steps a partition may have; a pair that needs more is refused. With
  /// it the work is bounded (see max_work()): ε alone allows ~1/ε steps, each
  /// checked on the full sample, which took minutes on extremely distorted pairs.
  int max_steps = 256;
  PartitionWork* work = nullptr;  ///< if set, receives what the build cost
};

/// Upper bound of PartitionWork::point_evaluations for these options when every
/// sample has at most `sample_points` points: at most max_steps + 1 steps,
/// each found with at most log2(1/ε) + 2 checks, plus max_rounds composite
/// checks of at most max_steps steps.
Index max_work(const AdaptiveOptions& options, Index sample_points);

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

/// The greedy strategy's step 1 on [a, b]: inner cuts in increasing order, each
/// step's min det J appended to `interval_min_det`. Throws warpfem::Error when no
/// step longer than ε from some t reaches min det J > 0.
std::vector<Real> greedy_partition(const VertexPath& path, Real a, Real b, const AdaptiveOptions& options,
                                   std::vector<Real>* interval_min_det = nullptr);

struct AdaptiveComposite {
  std::shared_ptr<const CompositeMeanValueMap> map;
  CompositeReport report;
};

/// Algorithm 1 (or the greedy partition, per options.strategy) plus the composite check. Throws
/// warpfem::Error if bijectivity cannot be reached with intervals ≥ ε (message: the interval and min det J).
AdaptiveComposite build_adaptive_composite(const VertexPath& path, const AdaptiveOptions& options = {});

/// The composite check and distortion statistics of any composite (also
/// uniform/explicit ones) on the standard Ω0 sample; does not throw on folds.
CompositeReport analyze_composite(const CompositeMeanValueMap& map, int sample_resolution);

}  // namespace warpfem::mapping
