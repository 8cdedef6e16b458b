// Compares composite harmonic maps (thesis Ch. 5) with composite mean value maps
// (Ch. 4) on the shipped example pairs and prints Markdown tables:
//   1. distortion (Table 5.2): min det J, mean/max conformal and isometric
//      distortion on a dense sample of Ω0, for composite mean value (adaptive),
//      composite harmonic with regular Λ and with optimized Λ' (bem, as the thesis);
//   2. boundary deviation of bem and mfs as the boundary nodes grow;
//   3. set-up time and evaluation time per point (values + Jacobians) per method.
//
// Run (Release):  build/bench/mapping_harmonic/compare_harmonic [--quick]

#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/environment.hpp"
#include "core/timer.hpp"
#include "mapping/distortion.hpp"
#include "mapping/harmonic/intermediate_polygon.hpp"
#include "mapping/harmonic/make_harmonic_map.hpp"
#include "mapping/make_map.hpp"
#include "mapping/polygon_sampling.hpp"

namespace wm = warpfem::mapping;
using warpfem::Index;
using warpfem::Point;
using warpfem::Points;
using warpfem::Real;

namespace {

/// 1. Reads examples/maps/<name>.json into a MapSpec.
wm::MapSpec load(const std::string& name) {
  const std::string file = std::string(WARPFEM_SOURCE_DIR) + "/examples/maps/" + name + ".json";
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, true, true).at("map");
  auto poly = [&](const char* key) {
    std::vector<Point<2>> v;
    for (const auto& p : j.at(key)) v.emplace_back(p.at(0).get<Real>(), p.at(1).get<Real>());
    return warpfem::Polygon(v, name + " " + key);
  };
  wm::MapSpec s;
  s.type = j.at("type");
  s.source = poly("source");
  s.target = poly("target");
  s.vertex_path = j.value("vertex_path", s.vertex_path);
  s.partition = j.value("partition", s.partition);
  s.sample_resolution = j.value("sample_resolution", s.sample_resolution);
  s.min_interval = j.value("min_interval", s.min_interval);
  s.origin = file;
  return s;
}

/// Distortion statistics on the uniform grid sample; min det J on the dense
/// bijectivity sample (grid + edge/corner clusters), where folds start.
wm::DistortionSummary distortion_of(const wm::Map<2>& f, const Points<2>& grid, const Points<2>& dense) {
  warpfem::Jacobians<2> J;
  f.jacobian(grid, J);
  wm::DistortionSummary s = wm::summarize_distortion<2>(J);
  f.jacobian(dense, J);
  s.min_det = wm::jacobian_determinants<2>(J).minCoeff();
  return s;
}

void row(const char* example, const std::string& method, const wm::DistortionSummary& s, double seconds) {
  std::printf("| %s | %s | %.3g | %.3f | %.4g | %.3f | %.4g | %.2f |\n", example, method.c_str(), s.min_det,
              s.conformal.mean, s.conformal.max, s.isometric.mean, s.isometric.max, seconds);
}

wm::MapSpec harmonic_spec(wm::MapSpec s, const char* method, const char* intermediate, int nodes) {
  s.type = "composite_harmonic";
  s.harmonic_method = method;
  s.intermediate = intermediate;
  s.boundary_nodes = nodes;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  warpfem::Environment env(argc, argv);
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const int resolution = quick ? 32 : 64;
  const int nodes = quick ? 256 : 512;
  const char* examples[] = {"square_to_dart", "star_to_bent_star", "square_to_gear"};

  // 2. Distortion table (thesis Table 5.2).
  std::printf("### Distortion: mean/max on grid_sample(Ω0, %d), min det J on bijectivity_sample(Ω0, %d)\n\n",
              resolution, resolution);
  std::printf(
      "| example | map | min det J | conformal mean | conformal max | isometric mean | isometric max | "
      "set-up s |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const char* name : examples) {
    const wm::MapSpec mv = load(name);
    const Points<2> grid = wm::grid_sample(*mv.source, resolution);
    const Points<2> dense = wm::bijectivity_sample(*mv.source, resolution);
    warpfem::Stopwatch w;
    const wm::MapPtr<2> f_mv = wm::make_map(mv);
    const double t_mv = w.seconds();
    row(name, "composite mean value (" + f_mv->describe().substr(f_mv->describe().find(',') + 2) + ")",
        distortion_of(*f_mv, grid, dense), t_mv);
    for (const char* inter : {"regular", "cyclic", "optimized"}) {
      w.reset();
      const auto f = wm::make_composite_harmonic(harmonic_spec(mv, "bem", inter, nodes));
      const double t = w.seconds();
      row(name, std::string("harmonic bem, ") + inter + " Λ", distortion_of(*f, grid, dense), t);
    }
    w.reset();
    const auto f_fem = wm::make_composite_harmonic(harmonic_spec(mv, "fem", "regular", nodes));
    row(name, "harmonic fem, regular Λ", distortion_of(*f_fem, grid, dense), w.seconds());
  }

  // 3. Boundary deviation of the smooth approximations (thesis Fig. 5.3, Table 5.1).
  std::printf(
      "\n### Boundary deviation max |φ(x) − g(x)| (x on ∂Ω moved 1e-7·diam inward, 64 points per edge)\n\n");
  std::printf(
      "| polygon → regular Λ | method | m = 32 | 64 | 128 | 256 | 512 | 1024 "
      "|\n|---|---|---|---|---|---|---|---|\n");
  for (const char* name : {"square_to_dart", "star_to_bent_star"}) {
    const wm::MapSpec s = load(name);
    const warpfem::Polygon& P = *s.target;
    for (wm::HarmonicMethod method : {wm::HarmonicMethod::bem, wm::HarmonicMethod::mfs}) {
      std::printf("| %s target | %s |", name, wm::to_string(method).c_str());
      for (Index m : {32, 64, 128, 256, 512, 1024}) {
        if (m < P.size()) {
          std::printf(" – |");
          continue;
        }
        wm::HarmonicOptions o;
        o.method = method;
        o.boundary_nodes = m;
        std::printf(" %.2e |",
                    wm::boundary_deviation(*wm::make_harmonic(P, wm::regular_polygon(P.size()), {}, o)));
      }
      std::printf("\n");
    }
  }

  // 4. Evaluation time per point (values + Jacobians), 10^4 random points of Ω0.
  const Index N = quick ? 2000 : 10000;
  std::printf("\n### Time: set-up and evaluation of f and J_f per point (%ld random points, 1 thread)\n\n",
              static_cast<long>(N));
  std::printf("| example | map | set-up s | µs / point |\n|---|---|---|---|\n");
  for (const char* name : {"square_to_dart", "square_to_gear"}) {
    const wm::MapSpec mv = load(name);
    const warpfem::Polygon& P = *mv.source;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<Real> ux(P.bbox_min().x(), P.bbox_max().x()),
        uy(P.bbox_min().y(), P.bbox_max().y());
    Points<2> x(N, 2);
    for (Index p = 0; p < N;) {
      const Real a = ux(rng), b = uy(rng);
      if (wm::inside_polygon(P, a, b)) x.row(p++) << a, b;
    }
    auto time_map = [&](const std::string& label, auto&& build) {
      warpfem::Stopwatch w;
      const wm::MapPtr<2> f = build();
      const double setup = w.seconds();
      Points<2> y;
      warpfem::Jacobians<2> J;
      w.reset();
      f->eval_with_jacobian(x, y, J);
      std::printf("| %s | %s | %.3f | %.2f |\n", name, label.c_str(), setup,
                  1e6 * w.seconds() / static_cast<double>(N));
    };
    time_map("composite mean value (adaptive)", [&] { return wm::make_map(mv); });
    for (const char* method : {"fem", "bem", "mfs"})
      time_map(std::string("harmonic ") + method + ", regular Λ, m = " + std::to_string(nodes),
               [&] { return wm::make_harmonic_map(harmonic_spec(mv, method, "regular", nodes)); });
  }
  return 0;
}
