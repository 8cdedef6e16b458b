#include "mapping/adaptive_partition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "core/error.hpp"
#include "core/log.hpp"
#include "mapping/barycentric_step.hpp"
#include "mapping/polygon_sampling.hpp"

namespace warpfem::mapping {
namespace {

// Every det J check goes through here, so PartitionWork counts all of it.
struct Checker {
  explicit Checker(const AdaptiveOptions& options)
      : o(options), work(options.work ? *options.work : scratch) {}
  Checker(const Checker&) = delete;
  Checker& operator=(const Checker&) = delete;

  const AdaptiveOptions& o;
  PartitionWork scratch;
  PartitionWork& work;

  Points<2> sample(const Polygon& from) const { return bijectivity_sample(from, o.sample_resolution); }

  /// min det J of the step from → to on `x`, a sample of `from`.
  Real step_min_det(const Polygon& from, const Points<2>& x, const Polygon& to) {
    ++work.step_checks;
    work.point_evaluations += x.rows();
    if (x.rows() == 0) return std::numeric_limits<Real>::infinity();
    const BarycentricStep step(from, to.vertices(), o.coordinates);
    Points<2> y;
    Jacobians<2> J;
    step.apply(x, y, &J);
    const VectorX det = jacobian_determinants<2>(J);
    return min_entry(det.data(), det.size());
  }
  Real step_min_det(const Polygon& from, const Polygon& to) { return step_min_det(from, sample(from), to); }
};

[[noreturn]] void fail(Real a, Real b, Real det, const AdaptiveOptions& o, const std::string& where) {
  std::ostringstream os;
  os.precision(17);
  os << "composite map is not bijective: " << where << " the step on [" << a << ", " << b
     << "] still has min det J = " << det
     << " and the interval has reached the minimum length epsilon = " << o.min_interval;
  throw Error(os.str(), {.file = "",
                         .key_path = "map.min_interval",
                         .hint = "decrease map.min_interval, raise map.sample_resolution, or try another "
                                 "map.vertex_path"});
}

/// The partition would need more than max_steps steps: the pair is too
/// distorted to be reached in bounded work.
[[noreturn]] void too_many_steps(Real a, Real b, Real det, const AdaptiveOptions& o,
                                 const std::string& where) {
  std::ostringstream os;
  os.precision(6);
  os << "composite map needs more than max_steps = " << o.max_steps << " steps: " << where << " the step on ["
     << a << ", " << b << "] has min det J = " << det
     << " and the partition has no steps left; the source and target are too far apart for this vertex path";
  throw Error(os.str(), {.file = "",
                         .key_path = "map.max_steps",
                         .hint = "try the other map.vertex_path (\"linear\" or \"intrinsic\"), \"type\": "
                                 "\"composite_harmonic\", or map in stages through intermediate targets; "
                                 "raising map.max_steps costs det J checks on the whole sample per step"});
}

// Algorithm 1 on [a, b]; `splits` counts the intervals split so far (each
// adds one step), so at most 2 max_steps − 1 intervals are ever checked.
void build(Checker& check, const VertexPath& path, Real a, const Polygon& Pa, const Points<2>& xa, Real b,
           const Polygon& Pb, std::vector<Real>& cuts, std::vector<Real>* dets, int& splits) {
  const AdaptiveOptions& o = check.o;
  const Real det = check.step_min_det(Pa, xa, Pb);
  if (det > 0) {
    if (dets) dets->push_back(det);
    return;
  }
  if (b - a <= o.min_interval) fail(a, b, det, o, "Algorithm 1:");
  if (splits + 1 >= o.max_steps) too_many_steps(a, b, det, o, "Algorithm 1:");
  ++splits;
  const Real c = 0.5 * (a + b);
  const Polygon Pc = path.polygon_at(c);
  build(check, path, a, Pa, xa, c, Pc, cuts, dets, splits);
  cuts.push_back(c);
  build(check, path, c, Pc, check.sample(Pc), b, Pb, cuts, dets, splits);
}

}  // namespace

Index max_work(const AdaptiveOptions& o, Index sample_points) {
  // Checks per greedy step: the whole rest, then halvings of an interval ≤ 1 down to ε.
  const Index halvings = static_cast<Index>(std::ceil(std::log2(1 / o.min_interval))) + 1;
  const Index steps = o.max_steps;
  const Index first_phase = steps * (halvings + 1);             // greedy; Algorithm 1 needs ≤ 2 max_steps
  const Index composite = Index{o.max_rounds} * steps + steps;  // rounds, then the report's own checks
  return sample_points * (first_phase + composite);
}

std::vector<Real> binary_partition(const VertexPath& path, Real a, Real b, const AdaptiveOptions& options,
                                   std::vector<Real>* interval_min_det) {
  Checker check(options);
  std::vector<Real> cuts;
  int splits = 0;
  const Polygon Pa = path.polygon_at(a);
  build(check, path, a, Pa, check.sample(Pa), b, path.polygon_at(b), cuts, interval_min_det, splits);
  return cuts;
}

std::vector<Real> greedy_partition(const VertexPath& path, Real a, Real b, const AdaptiveOptions& o,
                                   std::vector<Real>* interval_min_det) {
  Checker check(o);
  // Cut positions are resolved to 1/256 of [a, b] (or ε if larger): finer
  // positions would gain little length per step for many more checks.
  const Real resolution = std::max(o.min_interval, (b - a) / 256);
  std::vector<Real> cuts;
  Real t = a;
  Polygon Pt = path.polygon_at(a);
  const Polygon Pb = path.polygon_at(b);
  for (;;) {
    const Points<2> xt = check.sample(Pt);  // every step from t is checked on Ω_t's sample
    const Real whole = check.step_min_det(Pt, xt, Pb);
    if (whole >= o.greedy_min_det) {
      if (interval_min_det) interval_min_det->push_back(whole);
      return cuts;
    }
    if (static_cast<int>(cuts.size()) + 1 >= o.max_steps)
      too_many_steps(t, b, whole, o, "greedy partition (min det J below greedy_min_det):");
    // Bisect for the largest end e in (t, b) with min det J(Ω_t → Ω_e) >= greedy_min_det.
    Real lo = t, hi = b, lo_det = 0, hi_det = whole;
    Polygon Plo = Pt;
    while (hi - lo > resolution || (lo == t && hi - lo > o.min_interval)) {
      const Real mid = 0.5 * (lo + hi);
      Polygon Pm = path.polygon_at(mid);
      const Real d = check.step_min_det(Pt, xt, Pm);
      if (d >= o.greedy_min_det) {
        lo = mid, lo_det = d, Plo = std::move(Pm);
      } else {
        hi = mid, hi_det = d;
      }
    }
    if (lo == t) fail(t, hi, hi_det, o, "greedy partition (min det J below greedy_min_det):");
    cuts.push_back(lo);
    if (interval_min_det) interval_min_det->push_back(lo_det);
    t = lo;
    Pt = std::move(Plo);
  }
}

CompositeReport analyze_composite(const CompositeMeanValueMap& map, int sample_resolution) {
  CompositeReport r;
  r.times = map.times();
  const Points<2> x0 = bijectivity_sample(map.polygons().front(), sample_resolution);
  r.samples = x0.rows();
  MatrixX det;
  Jacobians<2> J;
  map.step_determinants(x0, det, nullptr, &J);
  r.step_min_det_along.resize(static_cast<std::size_t>(map.steps()));
  for (Index k = 0; k < map.steps(); ++k)
    r.step_min_det_along[static_cast<std::size_t>(k)] =
        x0.rows() ? min_entry(det.col(k).data(), det.rows()) : std::numeric_limits<Real>::infinity();
  r.distortion = summarize_distortion<2>(J);
  r.composite_min_det = x0.rows() ? r.distortion.min_det : std::numeric_limits<Real>::infinity();
  return r;
}

AdaptiveComposite build_adaptive_composite(const VertexPath& path, const AdaptiveOptions& o) {
  if (!(o.min_interval > 0) || o.sample_resolution < 2)
    throw Error("adaptive partition needs min_interval > 0 and sample_resolution >= 2",
                {.file = "", .key_path = "map.min_interval", .hint = ""});
  if (o.max_steps < 1)
    throw Error("adaptive partition needs max_steps >= 1",
                {.file = "", .key_path = "map.max_steps", .hint = ""});
  Checker check(o);
  // 1. Algorithm 1 (or the greedy partition) on [0, 1].
  std::vector<Real> dets;
  std::vector<Real> cuts = o.strategy == PartitionStrategy::greedy ? greedy_partition(path, 0, 1, o, &dets)
                                                                   : binary_partition(path, 0, 1, o, &dets);
  std::vector<Real> times{0};
  times.insert(times.end(), cuts.begin(), cuts.end());
  times.push_back(1);
  std::map<std::pair<Real, Real>, Real> known;  // Algorithm 1's min det J per accepted interval
  for (std::size_t k = 0; k < dets.size(); ++k) known[{times[k], times[k + 1]}] = dets[k];
  // 2. Composite check; split steps that fold along the pushed-forward sample.
  for (int round = 1;; ++round) {
    auto map = std::make_shared<const CompositeMeanValueMap>(path, times, o.coordinates);
    CompositeReport r = analyze_composite(*map, o.sample_resolution);
    ++check.work.composite_rounds;
    check.work.point_evaluations += r.samples * map->steps();
    r.rounds = round;
    std::vector<Real> refined{0};
    bool split = false;
    for (std::size_t k = 0; k + 1 < times.size(); ++k) {
      const Real a = times[k], b = times[k + 1];
      const Real det = r.step_min_det_along[k];
      if (!(det > 0)) {
        if (b - a <= o.min_interval || round >= o.max_rounds) fail(a, b, det, o, "composite check:");
        // the steps kept so far, this one split in two, and the rest
        const auto steps_after = refined.size() + 1 + (times.size() - k - 2);
        if (steps_after > static_cast<std::size_t>(o.max_steps))
          too_many_steps(a, b, det, o, "composite check (det J along the pushed-forward sample):");
        refined.push_back(0.5 * (a + b));
        split = true;
      }
      refined.push_back(b);
    }
    if (!split && r.composite_min_det > 0) {
      // per-step min det on each Ω_{t_k}'s own sample, for the report
      for (std::size_t k = 0; k + 1 < times.size(); ++k) {
        const auto it = known.find({times[k], times[k + 1]});
        r.step_min_det.push_back(
            it != known.end() ? it->second : check.step_min_det(map->polygons()[k], map->polygons()[k + 1]));
      }
      log::debug("adaptive composite: ", map->steps(), " steps, ", round,
                 " rounds, min det J_f = ", r.composite_min_det);
      return {map, std::move(r)};
    }
    if (!split) {
      // Every step is positive along the sample but the product of their
      // Jacobians is not (floating point loses it: cancellation, underflow or
      // overflow): splitting cannot help, and the same steps would be checked
      // again forever.
      std::ostringstream os;
      os.precision(6);
      os << "composite map is not bijective in floating point: every one of its " << map->steps()
         << " steps has det J > 0 along the sample, but the composite's min det J is " << r.composite_min_det
         << " (the product of the steps' Jacobians loses its sign or is not finite in floating point)";
      throw Error(os.str(), {.file = "",
                             .key_path = "map.target",
                             .hint = "the polygons span too many orders of magnitude (very short edges "
                                     "next to very long ones); rescale or simplify them"});
    }
    times = std::move(refined);
  }
}

}  // namespace warpfem::mapping
