// How the Jacobian of a config's map behaves under refinement: J_f at the cell
// centres of n × n grids over the source polygon's bounding box (points inside
// the polygon only), n = 64 … 2048. Prints per n the median, 99th and 99.9th
// percentiles and the maximum of σ1/σ2 (the pulled-back Laplacian's coefficient
// det J J⁻¹J⁻ᵀ has anisotropy (σ1/σ2)²) and the smallest det J_f. A maximum that
// keeps growing while the percentiles stay put marks a thin set of points where
// J_f is singular or depends on the direction of approach: the polygon's vertices.
// So then, per vertex, the largest σ1/σ2 and smallest det J_f in 720 directions
// at distances 1e-3, 1e-5, 1e-7: settled values mean a direction-dependent but
// bounded Jacobian, drifting ones a singular vertex (docs/multigrid.md: why
// multigrid iterations grow on such maps).
//
//   build/bench/mapping/map_distortion examples/study_gear64.json

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/environment.hpp"
#include "core/error.hpp"
#include "io/run_config.hpp"
#include "mapping/distortion.hpp"
#include "mapping/make_map.hpp"
#include "mapping/polygon_sampling.hpp"

using namespace warpfem;

namespace {
/// J_f next to every polygon vertex: in 720 directions across the source angle at
/// distances 1e-3, 1e-5, 1e-7, the largest σ1/σ2 and the smallest det J_f. A map
/// whose values settle is direction-dependent but bounded there; one whose det J_f
/// keeps falling (or σ1/σ2 keeps rising) is singular at the vertex.
void print_vertex_limits(const mapping::Map<2>& map, const Polygon& source, const Polygon& target) {
  std::printf("\nnext to the vertices (720 directions; distance 1e-3, 1e-5, 1e-7):\n");
  std::printf("vertex  angle source -> target   max sigma1/sigma2            min det J_f\n");
  int singular = 0;
  for (Index i = 0; i < source.size(); ++i) {
    const mapping::CornerWedge wedge = mapping::corner_wedge(source, i);
    const double start = wedge.start, span = wedge.angle,
                 target_span = mapping::corner_wedge(target, i).angle;
    constexpr int directions = 720;
    double ratio[3], det[3];
    int level = 0;
    for (const double r : {1e-3, 1e-5, 1e-7}) {
      Points<2> x0(directions, 2), x;
      for (int k = 0; k < directions; ++k) {
        const double t = start + span * (k + 0.5) / directions;
        x0.row(k) << source.vertex(i).x() + r * std::cos(t), source.vertex(i).y() + r * std::sin(t);
      }
      Jacobians<2> J;
      map.eval_with_jacobian(x0, x, J);
      ratio[level] = 0;
      for (Index k = 0; k < directions; ++k) {
        const auto [s1, s2] = mapping::extreme_singular_values<2>(J, k);
        ratio[level] = std::max(ratio[level], s1 / std::max(s2, 1e-300));
      }
      det[level++] = mapping::jacobian_determinants<2>(J).minCoeff();
    }
    const bool is_singular = det[2] < 0.5 * det[1] || ratio[2] > 2 * ratio[1];
    singular += is_singular ? 1 : 0;
    std::printf("%6ld  %6.1f -> %6.1f   %8.1f %8.1f %8.1f   %.2e %.2e %.2e%s\n", static_cast<long>(i),
                span * 180 / M_PI, target_span * 180 / M_PI, ratio[0], ratio[1], ratio[2], det[0], det[1],
                det[2], is_singular ? "  singular" : "");
  }
  std::printf("%d of %ld vertices singular\n", singular, static_cast<long>(source.size()));
}
}  // namespace

int main(int argc, char** argv) {
  Environment env(argc, argv);
  if (argc < 2) {
    std::fprintf(stderr, "usage: map_distortion <config.json with a \"map\" object>\n");
    return 2;
  }
  try {
    const std::string file = argv[1];
    const mapping::MapSpec spec =
        io::parse_required_map(io::ConfigNode(io::ConfigNode::parse_file(file), file));
    const mapping::MapPtr<2> map = mapping::make_map(spec);
    const Polygon& source = *spec.source;
    const Point<2> lo = source.bbox_min(), hi = source.bbox_max();
    std::printf("%s: %s\n", file.c_str(), map->describe().c_str());
    for (int n = 64; n <= 2048; n *= 2) {
      std::vector<Point<2>> inside;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          const Point<2> p(lo.x() + (a + 0.5) * (hi.x() - lo.x()) / n,
                           lo.y() + (b + 0.5) * (hi.y() - lo.y()) / n);
          if (source.side_of(p) > 0) inside.push_back(p);
        }
      Points<2> x0(static_cast<Index>(inside.size()), 2), x;
      for (std::size_t k = 0; k < inside.size(); ++k) x0.row(static_cast<Index>(k)) = inside[k].transpose();
      Jacobians<2> J;
      map->eval_with_jacobian(x0, x, J);
      std::vector<double> ratio(inside.size());
      for (Index p = 0; p < x0.rows(); ++p) {
        const auto [s1, s2] = mapping::extreme_singular_values<2>(J, p);
        ratio[static_cast<std::size_t>(p)] = s1 / std::max(s2, 1e-300);
      }
      const double min_det = mapping::jacobian_determinants<2>(J).minCoeff();
      std::sort(ratio.begin(), ratio.end());
      const auto q = [&](double f) {
        return ratio[static_cast<std::size_t>(f * static_cast<double>(ratio.size() - 1))];
      };
      std::printf(
          "n %5d (%8zu points): sigma1/sigma2 median %.2f, p99 %.1f, p99.9 %.1f, max %.1f; min det J_f "
          "%.4f\n",
          n, inside.size(), q(0.5), q(0.99), q(0.999), ratio.back(), min_det);
    }
    print_vertex_limits(*map, source, spec.target ? *spec.target : source);
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
