// Refusal is the rule: for every map type and harmonic method, on the shipped
// example maps and on polygon pairs chosen to be hard (stars, slivers, convex
// onto concave, a near-degenerate edge, many vertices), make_map() either
// refuses the map or returns one that the independent probe check
// (fold_probe.hpp) finds fold-free.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fold_probe.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/make_map.hpp"
#include "mapping/mean_value_certificate.hpp"
#include "mapping/polygon_sampling.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

using test::polygon;

Polygon ring(int n, const std::function<Real(Real)>& radius, const std::string& name) {
  std::vector<Point<2>> v;
  for (int i = 0; i < n; ++i) {
    const Real a = 2 * std::numbers::pi * i / n;
    v.emplace_back(radius(a) * std::cos(a), radius(a) * std::sin(a));
  }
  return polygon(v, name);
}

/// A square with k vertices per side (4k in all), counter-clockwise from (0, 0).
Polygon fine_square(int k) {
  std::vector<Point<2>> v;
  const Point<2> c[] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int s = 0; s < 4; ++s)
    for (int i = 0; i < k; ++i) v.push_back(c[s] + (c[(s + 1) % 4] - c[s]) * i / static_cast<Real>(k));
  return polygon(v, "16-vertex square");
}

/// The square's boundary pushed onto a wavy outline (same vertex count).
Polygon wavy(const Polygon& square) {
  std::vector<Point<2>> v;
  for (const Point<2>& p : square.vertices()) {
    const Point<2> d = p - Point<2>(0.5, 0.5);
    const Real a = std::atan2(d.y(), d.x());
    v.push_back(Point<2>(0.5, 0.5) + (0.55 + 0.12 * std::sin(5 * a)) * d.normalized());
  }
  return polygon(v, "wavy outline");
}

struct Pair {
  const char* name;
  Polygon source, target;
};

std::vector<Pair> pairs() {
  std::vector<Pair> p;
  p.push_back({"square_to_dart", test::diamond(), test::dart(-0.6)});
  p.push_back({"star_to_bent_star", test::star(), test::star(0.35)});
  p.push_back({"thin_star", test::star(0, 0.15), test::star(0.2, 0.15)});
  p.push_back({"convex_quad_to_concave", polygon({{0, 0}, {2, 0}, {2.2, 1.5}, {-0.3, 1.2}}, "convex quad"),
               polygon({{0, 0}, {2, 0}, {0.9, 0.4}, {-0.3, 1.2}}, "concave quad")});
  p.push_back({"l_shape_to_bent_l", polygon({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L"),
               polygon({{0, 0}, {2.2, 0.3}, {2.0, 1.2}, {1.3, 0.9}, {1.4, 2.1}, {-0.2, 1.8}}, "bent L")});
  p.push_back(
      {"sliver_to_arc",
       polygon({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 0.08}, {2, 0.08}, {1, 0.08}, {0, 0.08}}, "sliver"),
       polygon({{0, 0}, {1, 0.5}, {2, 0.5}, {3, 0}, {3, 0.08}, {2, 0.58}, {1, 0.58}, {0, 0.08}}, "arc")});
  p.push_back({"short_edge", polygon({{0, 0}, {1, 0}, {1, 0.999}, {0.999, 1}, {0, 1}}, "cut square"),
               polygon({{0, 0}, {1.2, 0.1}, {0.6, 0.55}, {0.599, 0.551}, {0.1, 1.1}}, "cut dart")});
  p.push_back({"concave32_to_circle", test::concave32(),
               ring(
                   32, [](Real) { return 1.0; }, "circle")});
  p.push_back({"square16_to_wavy", fine_square(4), wavy(fine_square(4))});
  p.push_back({"circle40_to_gear",
               ring(
                   40, [](Real) { return 1.0; }, "40-gon"),
               ring(
                   40, [](Real a) { return 1.0 + 0.18 * std::sin(8 * a); }, "40-gear")});
  return p;
}

struct MapKind {
  const char* name;
  void (*set)(MapSpec&);
};

const MapKind kKinds[] = {
    {"barycentric", [](MapSpec& s) { s.type = "barycentric"; }},
    {"mean_value_uniform4",
     [](MapSpec& s) {
       s.type = "composite_mean_value";
       s.partition = "uniform";
       s.steps = 4;
     }},
    {"mean_value_adaptive", [](MapSpec& s) { s.type = "composite_mean_value"; }},
    {"harmonic_fem",
     [](MapSpec& s) {
       s.type = "composite_harmonic";
       s.harmonic_method = "fem";
     }},
    {"harmonic_bem",
     [](MapSpec& s) {
       s.type = "composite_harmonic";
       s.harmonic_method = "bem";
     }},
    {"harmonic_mfs",
     [](MapSpec& s) {
       s.type = "composite_harmonic";
       s.harmonic_method = "mfs";
     }},
};

/// Builds the map; if make_map returns it, every probe must keep its orientation.
void expect_fold_free_or_refused(const MapSpec& spec, const std::string& label) {
  const test::ProbeSet probes = test::fold_probes(*spec.source);
  MapPtr<2> f;
  try {
    f = make_map(spec);
  } catch (const Error& e) {
    std::printf("[ %s ] refused: %s\n", label.c_str(), e.what());
    EXPECT_NE(std::string(e.what()).find(spec.origin), std::string::npos) << e.what();
    return;
  }
  try {
    const test::ProbeResult r = test::flipped_probes(*f, probes);
    std::printf("[ %s ] accepted: %ld of %ld probe triangles folded (%ld curved beyond double precision)\n",
                label.c_str(), static_cast<long>(r.folded), static_cast<long>(probes.triangles()),
                static_cast<long>(r.unresolved));
    EXPECT_EQ(r.folded, 0) << label << ": make_map returned a map that folds";
  } catch (const Error& e) {
    ADD_FAILURE() << label
                  << ": make_map accepted the map, but it cannot be evaluated at a probe: " << e.what();
  }
}

class FoldProbePairs : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(FoldProbePairs, FoldFreeOrRefused) {
  const auto [pair_index, kind_index] = GetParam();
  const Pair pair = pairs()[static_cast<std::size_t>(pair_index)];
  const MapKind& kind = kKinds[kind_index];
  MapSpec spec;
  kind.set(spec);
  spec.source = pair.source;
  spec.target = pair.target;
  spec.origin = std::string(pair.name) + ".json";
  expect_fold_free_or_refused(spec, std::string(pair.name) + " " + kind.name);
}

INSTANTIATE_TEST_SUITE_P(Pairs, FoldProbePairs,
                         ::testing::Combine(::testing::Range(0, 10), ::testing::Range(0, 6)),
                         [](const auto& info) {
                           return std::string(
                                      pairs()[static_cast<std::size_t>(std::get<0>(info.param))].name) +
                                  "_" + kKinds[std::get<1>(info.param)].name;
                         });

// The certificate (mapping/mean_value_certificate.hpp) on the shipped mean
// value examples and on every pair whose adaptive composite mean value map is
// built: a positive bound of det J_f on all of Ω0 but its vertices, never above
// det J_f at the map's check sample or at the probes' corners.
TEST(FoldProbePairs, EveryMeanValueMapBuiltIsCertified) {
  std::vector<std::pair<std::string, MapSpec>> specs;
  for (const char* example : {"square_to_dart", "star_to_bent_star", "square_to_gear"})
    specs.emplace_back(example, test::load_example(example));
  for (const Pair& pair : pairs()) {
    MapSpec spec;
    spec.type = "composite_mean_value";
    spec.source = pair.source;
    spec.target = pair.target;
    spec.origin = std::string(pair.name) + ".json";
    specs.emplace_back(pair.name, spec);
  }
  int certified = 0;
  for (const auto& [name, spec] : specs) {
    MapPtr<2> f;
    try {
      f = make_map(spec);
    } catch (const Error&) {
      continue;  // refused before any certificate; FoldFreeOrRefused covers it
    }
    const MapCertificate c = certify_map(*f);
    std::printf("[ %s ] %s\n", name.c_str(), c.summary().c_str());
    EXPECT_GT(c.lower_bound, 0) << name;
    EXPECT_LE(c.lower_bound, min_det_jacobian(*f, bijectivity_sample(*spec.source, 64))) << name;
    EXPECT_LE(c.lower_bound, min_det_jacobian(*f, test::fold_probes(*spec.source).corners)) << name;
    ++certified;
  }
  EXPECT_EQ(certified, static_cast<int>(specs.size()));
}

class FoldProbeExamples : public ::testing::TestWithParam<const char*> {};

TEST_P(FoldProbeExamples, FoldFreeOrRefused) {
  MapSpec spec = test::load_example(GetParam());
  expect_fold_free_or_refused(spec, GetParam());
  if (spec.type == "composite_harmonic")
    for (const char* method : {"fem", "bem", "mfs"}) {
      spec.harmonic_method = method;
      expect_fold_free_or_refused(spec, std::string(GetParam()) + " as " + method);
    }
}

INSTANTIATE_TEST_SUITE_P(Shipped, FoldProbeExamples,
                         ::testing::Values("square_to_dart", "square_to_gear", "star_to_bent_star",
                                           "harmonic_square_to_dart", "harmonic_square_to_gear",
                                           "harmonic_star_to_bent_star"));

TEST(FoldProbe, FindsTheFoldOfTheThesisCounterexample) {
  // The probe check itself must see a fold where there is one: the one-step
  // mean value map of thesis §2.1.2, built without make_map's check.
  MapSpec spec;
  spec.type = "barycentric";
  spec.source = test::diamond();
  spec.target = test::dart(-0.6);
  spec.origin = "counterexample.json";
  EXPECT_THROW(make_map(spec), Error);
  const auto folding = std::make_shared<const BarycentricMap>(test::diamond(), test::dart(-0.6));
  EXPECT_GT(test::flipped_probes(*folding, test::fold_probes(test::diamond())).folded, 0);
}

}  // namespace
}  // namespace warpfem::mapping
