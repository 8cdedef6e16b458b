// Exact composite mean value map against its adaptive interpolant
// (mapping/adaptive_interpolant.hpp) on one thread: f and J_f at N points of Ω0,
// for targets of 40, 192 and 1536 vertices. Rounds alternate exact and
// interpolated runs; the interpolated time includes building the interpolant.
// Times are CPU seconds of the process (one thread), medians over the rounds.
//
//   bench_map_interpolant [rounds=3] [million points, comma-separated = 1,4]
//                         [targets = square40,gear192,gear1536] [degree=10] [depth=12]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"
#include "io/config_node.hpp"
#include "io/run_config.hpp"
#include "mapping/adaptive_interpolant.hpp"
#include "mapping/make_map.hpp"

using namespace warpfem;

namespace {

// examples/maps/generate.py, curved_gear(): k vertices per straight edge of a
// 16-tooth gear (Ω0), moved onto the tip/root arcs and convex flanks (Ω1).
mapping::MapSpec curved_gear(int k) {
  const int teeth = 16;
  const Real r_tip = 1.0, r_root = 0.78, pitch = 2 * std::numbers::pi / teeth;
  const Real w_tip = 6.8 * std::numbers::pi / 180, w_flank = 4.5 * std::numbers::pi / 180,
             w_root = 6.7 * std::numbers::pi / 180;
  auto polar = [](Real rad, Real a) { return Point<2>(rad * std::cos(a), rad * std::sin(a)); };
  std::vector<Point<2>> source, target;
  for (int t = 0; t < teeth; ++t) {
    const Real a = -0.75 * std::numbers::pi + t * pitch;
    const Real cr[5] = {r_tip, r_tip, r_root, r_root, r_tip};
    const Real cb[5] = {a, a + w_tip, a + w_tip + w_flank, a + w_tip + w_flank + w_root, a + pitch};
    for (int e = 0; e < 4; ++e) {
      const Point<2> p0 = polar(cr[e], cb[e]), p1 = polar(cr[e + 1], cb[e + 1]);
      for (int j = 0; j < k; ++j) {
        const Real s = Real(j) / k;
        source.push_back(p0 + s * (p1 - p0));
        if (e == 0 || e == 2) {
          target.push_back(polar(cr[e], cb[e] + s * (cb[e + 1] - cb[e])));
        } else {
          const Real u = e == 1 ? 1 - (1 - s) * (1 - s) : s * s;
          target.push_back(polar(cr[e] + s * (cr[e + 1] - cr[e]), cb[e] + u * (cb[e + 1] - cb[e])));
        }
      }
    }
  }
  mapping::MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = Polygon::checked(source, "gear source");
  spec.target = Polygon::checked(target, "gear target");
  spec.origin = "curved gear, " + std::to_string(source.size()) + " vertices";
  return spec;
}

mapping::MapSpec square_to_gear() {
  const std::string file = std::string(WARPFEM_SOURCE_DIR) + "/examples/maps/square_to_gear.json";
  return io::parse_map_spec(io::ConfigNode(io::ConfigNode::parse_file(file), file).child("map"));
}

// Points of Ω0 in Morton order (as a mesh's quadrature points come, cell by cell).
Points<2> sample(const Polygon& p, Index n) {
  std::mt19937_64 rng(7);
  const Point<2> lo = p.bbox_min(), hi = p.bbox_max();
  std::uniform_real_distribution<Real> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  std::vector<std::pair<std::uint64_t, Point<2>>> pts;
  pts.reserve(static_cast<std::size_t>(n));
  auto spread = [](std::uint64_t v) {
    std::uint64_t r = 0;
    for (int b = 0; b < 20; ++b) r |= ((v >> b) & 1u) << (2 * b);
    return r;
  };
  // Rejection sampling against a fine raster of Ω0 (an exact test per point
  // would cost O(vertices)); points in cells cut by ∂Ω0 are dropped.
  const int R = 2048;
  std::vector<char> in(static_cast<std::size_t>(R) * R);
  for (int j = 0; j < R; ++j) {  // scanline: cells whose centre lies between crossings of ∂Ω0
    const Real y = lo.y() + (j + 0.5) / R * (hi.y() - lo.y());
    std::vector<Real> xs;
    for (Index e = 0; e < p.size(); ++e) {
      const Point<2>& a = p.vertex(e);
      const Point<2>& b = p.vertex(e + 1);
      if ((a.y() > y) != (b.y() > y)) xs.push_back(a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
    }
    std::sort(xs.begin(), xs.end());
    for (int i = 0; i < R; ++i) {
      const Real x = lo.x() + (i + 0.5) / R * (hi.x() - lo.x());
      const auto k = std::upper_bound(xs.begin(), xs.end(), x) - xs.begin();
      in[static_cast<std::size_t>(j) * R + i] = k % 2 == 1;
    }
  }
  while (static_cast<Index>(pts.size()) < n) {
    const Point<2> q(ux(rng), uy(rng));
    const int i = std::min(R - 1, static_cast<int>((q.x() - lo.x()) / (hi.x() - lo.x()) * R));
    const int j = std::min(R - 1, static_cast<int>((q.y() - lo.y()) / (hi.y() - lo.y()) * R));
    if (!in[static_cast<std::size_t>(j) * R + i]) continue;
    pts.emplace_back(
        spread(static_cast<std::uint64_t>(i * 512)) | (spread(static_cast<std::uint64_t>(j * 512)) << 1), q);
  }
  std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Points<2> x(n, 2);
  for (Index k = 0; k < n; ++k) x.row(k) = pts[static_cast<std::size_t>(k)].second.transpose();
  return x;
}

// f and J_f at all points, in chunks (as geometry evaluates them).
// CPU time of this (single-threaded) process: the shared machine's other load
// and the hypervisor's stolen time inflate wall clock far more than CPU time.
double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double evaluate(const mapping::Map<2>& f, const Points<2>& x, Points<2>& fx, Jacobians<2>& J) {
  const Index chunk = 1 << 16;
  const double start = cpu_seconds();
  fx.resize(x.rows(), 2);
  J.resize(x.rows(), 4);
  Points<2> in, out;
  Jacobians<2> Jc;
  for (Index b = 0; b < x.rows(); b += chunk) {
    const Index m = std::min(chunk, x.rows() - b);
    in = x.middleRows(b, m);
    f.eval_with_jacobian(in, out, Jc);
    fx.middleRows(b, m) = out;
    J.middleRows(b, m) = Jc;
  }
  return cpu_seconds() - start;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string t; std::getline(ss, t, ',');) out.push_back(t);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  set_thread_count(1);
  log::set_level(log::Level::warning);
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 3;
  const auto sizes = split(argc > 2 ? argv[2] : "1,4");
  const auto targets = split(argc > 3 ? argv[3] : "square40,gear192,gear1536");
  mapping::InterpolantOptions opt;
  if (argc > 4) opt.degree = std::atoi(argv[4]);
  if (argc > 5) opt.max_depth = std::atoi(argv[5]);
  std::printf("%-10s %6s %9s %9s %9s %9s %8s %11s %11s %9s %9s\n", "target", "Mpts", "exact_s", "interp_s",
              "build_s", "eval_s", "ratio", "exact_pt/s", "interp_pt/s", "f_err", "J_err");
  for (const std::string& name : targets) {
    const mapping::MapSpec spec = name == "square40"   ? square_to_gear()
                                  : name == "gear192"  ? curved_gear(3)
                                  : name == "gear1536" ? curved_gear(24)
                                                       : curved_gear(std::atoi(name.c_str() + 4) / 64);
    const mapping::MapPtr<2> exact = mapping::make_map(spec);
    for (const std::string& s : sizes) {
      const Index n = static_cast<Index>(std::atof(s.c_str()) * 1e6);
      const Points<2> x = sample(*spec.source, n);
      std::vector<double> te, ti, tb, tv;
      Real f_err = 0, J_err = 0;
      Points<2> fe, fi;
      Jacobians<2> Je, Ji;
      for (int r = 0; r < rounds; ++r) {
        te.push_back(evaluate(*exact, x, fe, Je));
        const double start = cpu_seconds();
        const mapping::AdaptiveInterpolant interp(exact, *spec.source, opt);
        tb.push_back(cpu_seconds() - start);
        if (r == 0) {
          const auto& st = interp.stats();
          std::printf(
              "# %s: %lld interpolated leaves, %lld exact, %lld outside, %lld exact evaluations, exact area "
              "%.3g, test errors f %.2g J %.2g\n",
              name.c_str(), (long long)st.interpolated_leaves, (long long)st.exact_leaves,
              (long long)st.outside_leaves, (long long)st.exact_evaluations, st.exact_area_fraction,
              st.max_f_error, st.max_J_error);
        }
        tv.push_back(evaluate(interp, x, fi, Ji));
        ti.push_back(tb.back() + tv.back());
      }
      const Point<2> diag = spec.source->bbox_max() - spec.source->bbox_min();
      for (Index p = 0; p < n; ++p) {
        f_err = std::max(f_err, (fe.row(p) - fi.row(p)).lpNorm<Eigen::Infinity>() / diag.norm());
        J_err = std::max(
            J_err, (Je.row(p) - Ji.row(p)).lpNorm<Eigen::Infinity>() / Je.row(p).lpNorm<Eigen::Infinity>());
      }
      std::printf("%-10s %6.2f %9.3f %9.3f %9.3f %9.3f %8.3f %11.3g %11.3g %9.2g %9.2g\n", name.c_str(),
                  n / 1e6, median(te), median(ti), median(tb), median(tv), median(ti) / median(te),
                  n / median(te), n / median(tv), f_err, J_err);
      std::fflush(stdout);
    }
  }
}
