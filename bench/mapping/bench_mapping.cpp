// Mapping benchmarks: mean value coordinates (values; values + gradients) side by
// side with CGAL's Barycentric_coordinates_2 on the same 32-vertex concave polygon
// and the same 10^6 interior points, an FMA-peak micro-benchmark to state ratios
// to peak, a 2-thread run, and the adaptive partition of the gear example.
//
// Run (Release, ideally -DWARPFEM_NATIVE=ON):  build/bench/mapping/bench_mapping
// Flop counts per point and vertex are hand-counted from the kernel
// (mapping/detail/mean_value_kernel.hpp): fma = 2, add/mul/div/sqrt = 1.

#include <CGAL/Barycentric_coordinates_2/Mean_value_coordinates_2.h>
#include <CGAL/Simple_cartesian.h>
#include <benchmark/benchmark.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <vector>

#include "core/threads.hpp"
#include "mapping/adaptive_partition.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/detail/mean_value_kernel.hpp"
#include "mapping/mean_value_coordinates.hpp"
#include "mapping/polygon_sampling.hpp"

namespace wm = warpfem::mapping;
using warpfem::Index;
using warpfem::Point;
using warpfem::Points;
using warpfem::Real;

namespace {

constexpr Index kPoints = 1'000'000;
constexpr Index kChunk = 256;  // points per call (an FE batch of ~40 P2 cells); outputs (196 KB) stay in L2
constexpr double kFlopsValues = 25, kFlopsValuesGradients = 53, kFlopsMap = 58;

const warpfem::Polygon& polygon32() {  // same as tests/mapping/test_polygons.hpp concave32()
  static const warpfem::Polygon P = [] {
    std::vector<Point<2>> v;
    for (int i = 0; i < 32; ++i) {
      const Real a = 2 * std::numbers::pi * i / 32;
      const Real r = 1.0 + 0.35 * std::sin(3 * a) + (i % 2 ? -0.25 : 0.0);
      v.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return warpfem::Polygon::checked(v, "concave 32-gon");
  }();
  return P;
}

/// 10^6 uniformly random interior points, split into chunks.
const std::vector<Points<2>>& chunks() {
  static const std::vector<Points<2>> c = [] {
    std::mt19937_64 rng(42);
    const auto& P = polygon32();
    std::uniform_real_distribution<Real> ux(P.bbox_min().x(), P.bbox_max().x()),
        uy(P.bbox_min().y(), P.bbox_max().y());
    std::vector<Points<2>> out;
    Index made = 0;
    while (made < kPoints) {
      const Index n = std::min(kChunk, kPoints - made);
      Points<2> x(n, 2);
      for (Index p = 0; p < n;) {
        const Real a = ux(rng), b = uy(rng);
        if (wm::inside_polygon(P, a, b)) x.row(p++) << a, b;
      }
      out.push_back(std::move(x));
      made += n;
    }
    return out;
  }();
  return c;
}

void set_counters(benchmark::State& state, double flops_per_pv) {
  const double pts = static_cast<double>(state.iterations()) * kPoints;
  state.counters["points/s"] = benchmark::Counter(pts, benchmark::Counter::kIsRate);
  if (flops_per_pv > 0)
    state.counters["FLOP/s"] = benchmark::Counter(pts * 32 * flops_per_pv, benchmark::Counter::kIsRate);
}

// Compiled with the same runtime dispatch as the kernels, so the peak is the
// machine's, not the portable baseline's.
WARPFEM_KERNEL_CLONES void fma_chains(double* __restrict acc, double a, double b, int repeats) {
  // Local accumulators stay in registers across the repeats (no memory round trip
  // per multiply-add); 128 lanes = 16 AVX-512 registers of independent chains.
  double v[128];
  for (int l = 0; l < 128; ++l) v[l] = acc[l];
  for (int r = 0; r < repeats; ++r)
    for (int l = 0; l < 128; ++l) v[l] = v[l] * a + b;
  for (int l = 0; l < 128; ++l) acc[l] = v[l];
}

void BM_FmaPeak(benchmark::State& state) {
  // 128 independent multiply-add chains: enough to fill both FMA pipes at any vector width.
  alignas(64) double acc[128];
  for (int l = 0; l < 128; ++l) acc[l] = 1.0 + l * 1e-3;
  const double a = 0.9999999, b = 1e-7;
  constexpr int kRepeat = 1 << 14;
  for (auto _ : state) {
    fma_chains(acc, a, b, kRepeat);
    benchmark::DoNotOptimize(acc);
  }
  state.counters["FLOP/s"] = benchmark::Counter(static_cast<double>(state.iterations()) * kRepeat * 128 * 2,
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FmaPeak);

void BM_Warpfem_MVC_Values(benchmark::State& state) {
  const wm::PolygonArrays P(polygon32());
  warpfem::MatrixX phi;
  for (auto _ : state)
    for (const auto& x : chunks()) {
      wm::mean_value_coordinates(P, x, phi);
      benchmark::DoNotOptimize(phi.data());
    }
  set_counters(state, kFlopsValues);
}
BENCHMARK(BM_Warpfem_MVC_Values)->Unit(benchmark::kMillisecond);

void BM_Warpfem_MVC_ValuesGradients(benchmark::State& state) {
  const wm::PolygonArrays P(polygon32());
  warpfem::MatrixX phi, dx, dy;
  for (auto _ : state)
    for (const auto& x : chunks()) {
      wm::mean_value_coordinates(P, x, phi, dx, dy);
      benchmark::DoNotOptimize(phi.data());
    }
  set_counters(state, kFlopsValuesGradients);
}
BENCHMARK(BM_Warpfem_MVC_ValuesGradients)->Unit(benchmark::kMillisecond);

void BM_Warpfem_MVC_ValuesGradients_2Threads(benchmark::State& state) {
  // The library's own threading (core/threads.hpp: dynamic scheduling of the
  // chunks). Output matrices come from a pool that outlives the iterations, as
  // the 1-thread benchmark reuses its own (fresh ones per piece would add page
  // faults to the 2-thread figure only).
  const wm::PolygonArrays P(polygon32());
  const auto& c = chunks();
  const int before = warpfem::thread_count();
  warpfem::set_thread_count(2);
  struct Outputs {
    warpfem::MatrixX phi, dx, dy;
  };
  std::vector<std::unique_ptr<Outputs>> pool;
  std::mutex pool_mutex;
  for (auto _ : state)
    warpfem::parallel_for(static_cast<Index>(c.size()), 1, [&](Index begin, Index end) {
      std::unique_ptr<Outputs> out;
      {
        const std::lock_guard<std::mutex> lock(pool_mutex);
        if (!pool.empty()) {
          out = std::move(pool.back());
          pool.pop_back();
        }
      }
      if (!out) out = std::make_unique<Outputs>();
      for (Index k = begin; k < end; ++k) {
        wm::mean_value_coordinates(P, c[static_cast<std::size_t>(k)], out->phi, out->dx, out->dy);
        benchmark::DoNotOptimize(out->phi.data());
      }
      const std::lock_guard<std::mutex> lock(pool_mutex);
      pool.push_back(std::move(out));
    });
  warpfem::set_thread_count(before);
  set_counters(state, kFlopsValuesGradients);
}
BENCHMARK(BM_Warpfem_MVC_ValuesGradients_2Threads)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Warpfem_Map_EvalJacobian(benchmark::State& state) {
  // f and J_f of a one-step mean value map: the fused kernel used by the composite maps
  std::vector<Point<2>> target = polygon32().vertices();
  for (auto& v : target) v = 1.1 * v + Point<2>(0.1 * v.y(), 0);
  const wm::BarycentricMap f(polygon32(), warpfem::Polygon(target, "target"));
  Points<2> y;
  warpfem::Jacobians<2> J;
  for (auto _ : state)
    for (const auto& x : chunks()) {
      f.eval_with_jacobian(x, y, J);
      benchmark::DoNotOptimize(J.data());
    }
  set_counters(state, kFlopsMap);
}
BENCHMARK(BM_Warpfem_Map_EvalJacobian)->Unit(benchmark::kMillisecond);

using K = CGAL::Simple_cartesian<double>;
std::vector<K::Point_2> cgal_polygon() {
  std::vector<K::Point_2> v;
  for (const auto& p : polygon32().vertices()) v.emplace_back(p.x(), p.y());
  return v;
}

void BM_CGAL_MVC_Values_Default(benchmark::State& state) {
  // the documented free function, default policy (PRECISE_WITH_EDGE_CASES)
  const auto poly = cgal_polygon();
  std::vector<double> out;
  out.reserve(32);
  for (auto _ : state)
    for (const auto& x : chunks())
      for (Index p = 0; p < x.rows(); ++p) {
        out.clear();
        CGAL::Barycentric_coordinates::mean_value_coordinates_2(poly, K::Point_2(x(p, 0), x(p, 1)),
                                                                std::back_inserter(out));
        benchmark::DoNotOptimize(out.data());
      }
  set_counters(state, 0);
}
BENCHMARK(BM_CGAL_MVC_Values_Default)->Unit(benchmark::kMillisecond);

void BM_CGAL_MVC_Values_Fast(benchmark::State& state) {
  // a reused coordinate object with the FAST_WITH_EDGE_CASES policy (CGAL's fastest safe setting)
  const auto poly = cgal_polygon();
  CGAL::Barycentric_coordinates::Mean_value_coordinates_2<std::vector<K::Point_2>, K> mvc(
      poly, CGAL::Barycentric_coordinates::Computation_policy_2::FAST_WITH_EDGE_CASES);
  std::vector<double> out;
  out.reserve(32);
  for (auto _ : state)
    for (const auto& x : chunks())
      for (Index p = 0; p < x.rows(); ++p) {
        out.clear();
        mvc(K::Point_2(x(p, 0), x(p, 1)), std::back_inserter(out));
        benchmark::DoNotOptimize(out.data());
      }
  set_counters(state, 0);
}
BENCHMARK(BM_CGAL_MVC_Values_Fast)->Unit(benchmark::kMillisecond);

void BM_AdaptivePartition_Gear512(benchmark::State& state) {
  std::ifstream in(std::string(WARPFEM_SOURCE_DIR) + "/examples/maps/square_to_gear.json");
  const nlohmann::json j = nlohmann::json::parse(in).at("map");
  auto poly = [&](const char* key) {
    std::vector<Point<2>> v;
    for (const auto& p : j.at(key)) v.emplace_back(p.at(0).get<Real>(), p.at(1).get<Real>());
    return warpfem::Polygon::checked(v, key);
  };
  const wm::VertexPath path(poly("source"), poly("target"), wm::VertexPathType::linear);
  wm::AdaptiveOptions o;
  o.sample_resolution = 512;
  Index steps = 0, samples = 0;
  for (auto _ : state) {
    const auto a = wm::build_adaptive_composite(path, o);
    steps = a.report.steps();
    samples = a.report.samples;
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["samples"] = static_cast<double>(samples);
}
BENCHMARK(BM_AdaptivePartition_Gear512)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
