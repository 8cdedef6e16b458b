#include "mapping/harmonic/intermediate_optimizer.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "mapping/harmonic/composite_harmonic_map.hpp"
#include "mapping/harmonic/intermediate_polygon.hpp"
#include "mapping/polygon_sampling.hpp"

namespace warpfem::mapping {

Real distortion_energy(const HarmonicMapPtr& phi0, const HarmonicMapPtr& phi1, const Points<2>& sample,
                       const std::string& energy, DistortionSummary* summary) {
  if (energy != "conformal" && energy != "isometric")
    throw Error(
        "unknown distortion energy \"" + energy + "\"",
        {.file = "", .key_path = "map.distortion_energy", .hint = "use \"conformal\" or \"isometric\""});
  const CompositeHarmonicMap f(phi0, phi1);
  Jacobians<2> J;
  f.jacobian(sample, J);
  const DistortionSummary s = summarize_distortion<2>(J);
  if (summary) *summary = s;
  if (!(s.min_det > 0)) return std::numeric_limits<Real>::infinity();
  return energy == "conformal" ? s.conformal.mean : s.isometric.mean;
}

IntermediateOptimization optimize_intermediate(const HarmonicMapPtr& phi0, const HarmonicMapPtr& phi1,
                                               const IntermediateOptimizerOptions& o) {
  const Points<2> sample = grid_sample(phi0->domain(), o.sample_resolution);
  IntermediateOptimization out;
  std::vector<Point<2>> w = phi0->image().vertices();
  const std::string name = phi0->image().name();
  auto energy = [&](const std::vector<Point<2>>& v, DistortionSummary* s = nullptr) {
    ++out.energy_evaluations;
    const Polygon L(v, name);
    return distortion_energy(phi0->with_image(L), phi1->with_image(L), sample, o.energy, s);
  };
  Real E = energy(w, &out.before);
  out.energy_before = E;
  const Real h = 1e-4 * diameter(phi0->image());
  const std::size_t n = w.size();
  auto local_length = [&](std::size_t k) {  // steps scale with the shorter adjacent edge
    return std::min((w[k] - w[(k + n - 1) % n]).norm(), (w[(k + 1) % n] - w[k]).norm());
  };
  std::vector<Real> tau(w.size(), o.initial_step);
  for (int sweep = 0; sweep < o.sweeps && std::isfinite(E); ++sweep) {
    for (std::size_t k = 0; k < w.size(); ++k) {
      Point<2> g;
      for (int c = 0; c < 2; ++c) {
        std::vector<Point<2>> wp = w, wm = w;
        wp[k](c) += h;
        wm[k](c) -= h;
        g(c) = (energy(wp) - energy(wm)) / (2 * h);
      }
      if (!g.allFinite() || g.norm() == 0) continue;
      const Point<2> dir = -g.normalized();
      bool moved = false;
      for (Real t = tau[k]; t > 1e-4 * o.initial_step && !moved; t *= 0.5) {
        std::vector<Point<2>> trial = w;
        trial[k] += t * local_length(k) * dir;
        if (!is_strictly_convex(trial)) continue;
        const Real Et = energy(trial);
        if (Et < E) {
          w = trial;
          E = Et;
          tau[k] = std::min(2 * t, 0.5);
          moved = true;
        }
      }
      if (!moved) tau[k] *= 0.25;
    }
  }
  out.polygon = Polygon(w, "optimized " + std::to_string(w.size()) + "-gon");
  out.energy_after = energy(w, &out.after);
  return out;
}

}  // namespace warpfem::mapping
