// Barycentric and composite maps: the thesis §2.1.2 counterexample, bijectivity
// of the adaptive composite, Jacobians, the backward map (§4.3), distortion.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

#include "core/error.hpp"
#include "mapping/adaptive_partition.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/barycentric_step.hpp"
#include "mapping/composite_mean_value_map.hpp"
#include "mapping/distortion.hpp"
#include "mapping/make_map.hpp"
#include "mapping/polygon_sampling.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

using test::jacobian_fd_error;

/// Boundary behaviour every barycentric map shares: vertices to vertices, edges linearly to edges.
void expect_boundary_reproduced(const Map<2>& f, const Polygon& from, const Polygon& to) {
  const Index n = from.size();
  Points<2> x(4 * n, 2), y(4 * n, 2);
  for (Index i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k) {
      const Real mu = k / 4.0;
      x.row(4 * i + k) = ((1 - mu) * from.vertex(i) + mu * from.vertex(i + 1)).transpose();
      y.row(4 * i + k) = ((1 - mu) * to.vertex(i) + mu * to.vertex(i + 1)).transpose();
    }
  Points<2> fx;
  f.eval(x, fx);
  EXPECT_LT((fx - y).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(BarycentricMap, CounterexampleFoldsInOneStep) {
  // thesis §2.1.2: moving one vertex of the square far enough folds any barycentric map
  const BarycentricMap f(test::diamond(), test::dart());
  EXPECT_LT(min_det_jacobian(f, bijectivity_sample(test::diamond(), 64)), 0.0);
  expect_boundary_reproduced(f, test::diamond(), test::dart());
}

TEST(BarycentricMap, JacobianMatchesCentralDifferences) {
  for (auto c : {Coordinates::mean_value, Coordinates::wachspress, Coordinates::discrete_harmonic}) {
    const BarycentricMap f(test::convex6(),
                           test::polygon({{0, 0}, {2, -0.5}, {3, 1}, {2.5, 2}, {1.2, 2.9}, {-1, 1}}, "t"), c);
    EXPECT_LT(jacobian_fd_error(f, grid_sample(test::convex6(), 12), 1e-6), 1e-6) << to_string(c);
  }
}

TEST(CompositeMap, AdaptiveCompositeUnfoldsTheCounterexample) {
  const VertexPath path(test::diamond(), test::dart(), VertexPathType::linear);
  const AdaptiveComposite a = build_adaptive_composite(path, {.sample_resolution = 64, .min_interval = 1e-4});
  const CompositeReport& r = a.report;
  std::printf("[ dart ] %ld steps, composite min det J = %.4g, conformal mean/max %.4g/%.4g\n",
              static_cast<long>(r.steps()), r.composite_min_det, r.distortion.conformal.mean,
              r.distortion.conformal.max);
  EXPECT_GT(r.steps(), 1);
  EXPECT_GT(r.composite_min_det, 0.0);
  ASSERT_EQ(r.step_min_det.size(), static_cast<std::size_t>(r.steps()));
  for (Real d : r.step_min_det) EXPECT_GT(d, 0.0);
  for (Real d : r.step_min_det_along) EXPECT_GT(d, 0.0);
  EXPECT_EQ(r.times.front(), 0.0);
  EXPECT_EQ(r.times.back(), 1.0);
  EXPECT_GE(r.distortion.conformal.mean, 2.0);
  EXPECT_TRUE(std::isfinite(r.distortion.conformal.max));
  // an independent, finer sample agrees
  EXPECT_GT(min_det_jacobian(*a.map, bijectivity_sample(test::diamond(), 157)), 0.0);
  expect_boundary_reproduced(*a.map, test::diamond(), test::dart());
  EXPECT_LT(jacobian_fd_error(*a.map, grid_sample(test::diamond(), 10), 1e-6), 1e-6);
}

/// min det J_f in `directions` directions across the interior wedge of every vertex, at distance r.
Real min_det_next_to_vertices(const Map<2>& f, const Polygon& p, Real r, int directions = 720) {
  Real worst = std::numeric_limits<Real>::infinity();
  for (Index i = 0; i < p.size(); ++i) {
    const CornerWedge wedge = corner_wedge(p, i);
    Points<2> x(directions, 2);
    for (int k = 0; k < directions; ++k) {
      const Real t = wedge.start + wedge.angle * (k + 0.5) / directions;
      x.row(k) = (p.vertex(i) + r * Point<2>(std::cos(t), std::sin(t))).transpose();
    }
    worst = std::min(worst, min_det_jacobian(f, x));
  }
  return worst;
}

// Next to a vertex J_f depends only on the direction (it is homogeneous of degree 0 there), and a
// fold can fill a narrow wedge of directions: the 2-step map the adaptive partition used to accept
// for this bent L has det J_f < 0 at distances ≤ 1e-5 from the re-entrant corner, in a wedge of
// about 10° that five sample directions per corner missed.
TEST(CompositeMap, AdaptivePartitionSeesFoldsInNarrowWedgesAtVertices) {
  MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = test::polygon({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L-shape");
  spec.target = test::polygon({{0, 0}, {2, 0}, {2.2, 1.4}, {1.3, 0.8}, {1.1, 2}, {-0.2, 1.8}}, "bent L");
  const MapPtr<2> f = make_map(spec);
  for (const Real r : {1e-3, 1e-5, 1e-7})
    EXPECT_GT(min_det_next_to_vertices(*f, *spec.source, r), 0.0) << "fold at distance " << r;
  const auto two_steps = std::make_shared<CompositeMeanValueMap>(
      VertexPath(*spec.source, *spec.target, VertexPathType::linear), std::vector<Real>{0.0, 0.5, 1.0});
  EXPECT_LT(min_det_next_to_vertices(*two_steps, *spec.source, 1e-5), 0.0)
      << "the example no longer folds in two steps; it does not test the corner sample";
}

TEST(CompositeMap, ThrowsWhenEpsilonIsReachedWithoutBijectivity) {
  const VertexPath path(test::diamond(), test::dart(-0.9), VertexPathType::linear);
  try {
    build_adaptive_composite(path, {.sample_resolution = 32, .min_interval = 0.6});
    FAIL() << "expected warpfem::Error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("not bijective"), std::string::npos) << what;
    EXPECT_NE(what.find("min det J = -"), std::string::npos) << what;
    EXPECT_NE(what.find("[0.5, 1]"), std::string::npos) << what;
    EXPECT_EQ(e.context().key_path, "map.min_interval");
  }
}

TEST(CompositeMap, IdenticalPolygonsGiveTheIdentity) {
  const CompositeMeanValueMap f(VertexPath(test::star(), test::star()), uniform_partition(5));
  const Points<2> x = bijectivity_sample(test::star(), 20);
  Points<2> y;
  Jacobians<2> J;
  f.eval_with_jacobian(x, y, J);
  EXPECT_EQ((y - x).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((jacobian_determinants<2>(J).array() - 1).abs().maxCoeff(), 1e-12);
}

TEST(CompositeMap, BackwardMapApproachesTheInverse) {
  // thesis Fig. 4.7: g_m ∘ f_m → id for uniform partitions (star -> bent star)
  const VertexPath path(test::star(), test::star(0.5), VertexPathType::linear);
  const Points<2> x = grid_sample(test::star(), 24);
  Real previous = 1e300;
  for (int m : {10, 100, 1000}) {
    const CompositeMeanValueMap f(path, uniform_partition(m));
    const CompositeMeanValueMap g = f.backward();
    const Real err = round_trip_error(f, g, x);
    std::printf("[ star ] m = %4d: max |x - g(f(x))| = %.3e\n", m, err);
    EXPECT_LT(err, 0.5 * previous) << "m = " << m;
    previous = err;
  }
  EXPECT_LT(previous, 1e-2);
}

TEST(CompositeMap, RejectsBadPartitions) {
  const VertexPath path(test::diamond(), test::dart());
  EXPECT_THROW(CompositeMeanValueMap(path, {0, 0.5, 0.5, 1}), Error);
  EXPECT_THROW(CompositeMeanValueMap(path, {0, 0.7}), Error);
  EXPECT_THROW(uniform_partition(0), Error);
}

TEST(Distortion, KnownJacobians) {
  Jacobians<2> J(4, 4);
  J.row(0) << 1, 0, 0, 1;   // identity
  J.row(1) << 0, -2, 2, 0;  // rotation by 90° and scaling by 2
  J.row(2) << 1, 1, 0, 1;   // shear: σ = golden ratio and its inverse
  J.row(3) << 1, 0, 0, -1;  // reflection (fold)
  VectorX c, i;
  distortion<2>(J, c, i);
  const Real g = (1 + std::sqrt(5.0)) / 2;
  EXPECT_NEAR(c(0), 2, 1e-15);
  EXPECT_NEAR(i(0), 1, 1e-15);
  EXPECT_NEAR(c(1), 2, 1e-15);
  EXPECT_NEAR(i(1), 2, 1e-15);
  EXPECT_NEAR(c(2), g * g + 1 / (g * g), 1e-12);
  EXPECT_NEAR(i(2), g, 1e-12);
  EXPECT_TRUE(std::isinf(c(3)) && std::isinf(i(3)));
  // the 3D path agrees with the closed form on a 2D-embedded case
  Jacobians<3> K = Jacobians<3>::Zero(1, 9);
  K(0, 0) = 1, K(0, 1) = 1, K(0, 4) = 1, K(0, 8) = 1;
  const auto [s1, s3] = extreme_singular_values<3>(K, 0);
  EXPECT_NEAR(s1, g, 1e-12);
  EXPECT_NEAR(s3, 1 / g, 1e-12);
}

class Examples : public ::testing::TestWithParam<const char*> {};

TEST_P(Examples, AdaptiveCompositeIsBijective) {
  const MapSpec spec = test::load_example(GetParam());
  const MapPtr<2> f = make_map(spec);
  const auto* c = dynamic_cast<const CompositeMeanValueMap*>(f.get());
  ASSERT_NE(c, nullptr);
  const CompositeReport r = analyze_composite(*c, 2 * spec.sample_resolution);  // finer than the build sample
  std::printf(
      "[ %s ] %ld steps, min det J_f = %.4g, conformal mean %.4g max %.4g, isometric mean %.4g max %.4g\n",
      GetParam(), static_cast<long>(r.steps()), r.composite_min_det, r.distortion.conformal.mean,
      r.distortion.conformal.max, r.distortion.isometric.mean, r.distortion.isometric.max);
  EXPECT_GT(r.composite_min_det, 0.0);
  expect_boundary_reproduced(*f, *spec.source, *spec.target);
}

/// An example map built twice: with Algorithm 1 and with the greedy partition.
struct BothPartitions {
  MapSpec spec;
  std::shared_ptr<const CompositeMeanValueMap> binary, greedy;
};

BothPartitions both_partitions(const std::string& example) {
  BothPartitions out{test::load_example(example), nullptr, nullptr};
  out.binary = std::dynamic_pointer_cast<const CompositeMeanValueMap>(make_map(out.spec));
  out.spec.partition = "greedy";
  out.greedy = std::dynamic_pointer_cast<const CompositeMeanValueMap>(make_map(out.spec));
  return out;
}

TEST_P(Examples, GreedyPartitionIsBijective) {
  const auto [spec, b, g] = both_partitions(GetParam());
  ASSERT_NE(b, nullptr);
  ASSERT_NE(g, nullptr);
  const CompositeReport r = analyze_composite(*g, 2 * spec.sample_resolution);
  std::printf("[ %s ] greedy: %ld steps (Algorithm 1: %ld), min det J_f = %.4g\n", GetParam(),
              static_cast<long>(g->steps()), static_cast<long>(b->steps()), r.composite_min_det);
  EXPECT_GT(r.composite_min_det, 0.0);
  expect_boundary_reproduced(*g, *spec.source, *spec.target);
  // Every step is bijective on its own sample, not only the composite.
  for (Index k = 0; k < g->steps(); ++k) {
    const auto& P = g->polygons();
    const BarycentricStep step(P[static_cast<std::size_t>(k)], P[static_cast<std::size_t>(k) + 1].vertices(),
                               Coordinates::mean_value);
    const Points<2> x = bijectivity_sample(P[static_cast<std::size_t>(k)], spec.sample_resolution);
    Points<2> y;
    Jacobians<2> J;
    step.apply(x, y, &J);
    EXPECT_GT(jacobian_determinants<2>(J).minCoeff(), 0.0) << "step " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Mapping, Examples,
                         ::testing::Values("square_to_dart", "star_to_bent_star", "square_to_gear"));

TEST(CompositeMap, GreedyPartitionNeedsFewerStepsForTheGear) {
  // Algorithm 1 only cuts at dyadic times (7 steps for the gear); the greedy steps
  // end wherever min det J reaches the margin. (It may also need more steps than
  // Algorithm 1 when a single step is bijective but below the margin: the bent star.)
  const auto [spec, b, g] = both_partitions("square_to_gear");
  ASSERT_NE(b, nullptr);
  ASSERT_NE(g, nullptr);
  EXPECT_LT(g->steps(), b->steps());
}

TEST(CompositeMap, GreedyPartitionFailsWithTheIntervalWhenNoStepReachesTheThreshold) {
  // The §2.1.2 counterexample with a threshold no step can keep: a clear error, no map.
  MapSpec spec = test::load_example("square_to_dart");
  spec.partition = "greedy";
  spec.greedy_min_det = 0.98;
  spec.min_interval = 1e-2;
  try {
    (void)make_map(spec);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("greedy partition"), std::string::npos) << e.what();
  }
}

TEST(CompositeMap, ExtremelyDistortedPairEndsWithinBoundedWork) {
  // A 4-gon with a vertex far out at (112, −1) onto one spread over [0, 103]
  // (found by fuzz_make_map): along the intrinsic vertex path the greedy steps
  // are short (30 of them here), and ε alone allowed ~1/ε steps, each checked
  // on the whole sample. max_steps bounds the work: the pair is refused naming
  // it, or mapped with at most max_steps steps.
  const Polygon source =
      test::polygon({{-0.75, 0}, {112, -1}, {0, 1.03125}, {0.13671875, 0.99609375}}, "far vertex");
  const Polygon target =
      test::polygon({{9.00390625, 0}, {102.99609375, 0.99609375}, {0, 0}, {1.375, 0}}, "target");
  const VertexPath path(source, target, VertexPathType::intrinsic);
  constexpr int resolution = 16;
  // every sample: at most resolution² grid points plus (8 + 23) × 6 clustered at each of the 4 vertices
  const Index sample_points = resolution * resolution + 4 * (8 + 23) * 6;
  for (const int max_steps : {8, 256}) {
    PartitionWork work;
    const AdaptiveOptions o{.sample_resolution = resolution,
                            .min_interval = 1e-3,
                            .strategy = PartitionStrategy::greedy,
                            .max_steps = max_steps,
                            .work = &work};
    try {
      const AdaptiveComposite a = build_adaptive_composite(path, o);
      EXPECT_EQ(max_steps, 256) << "8 steps cannot reach min det J >= 0.2 on every step";
      EXPECT_GT(a.report.composite_min_det, 0);
      EXPECT_GT(a.report.steps(), 8);
      EXPECT_LE(a.report.steps(), max_steps);
    } catch (const Error& e) {
      EXPECT_EQ(max_steps, 8) << e.what();
      EXPECT_EQ(e.context().key_path, "map.max_steps") << e.what();
      EXPECT_NE(e.message().find("more than max_steps = 8 steps"), std::string::npos) << e.what();
      EXPECT_FALSE(e.context().hint.empty());
    }
    EXPECT_GT(work.step_checks, 0);
    EXPECT_LE(work.point_evaluations, max_work(o, sample_points)) << work.step_checks << " checks";
  }
}

TEST(CompositeMap, APairWhoseCompositeDeterminantIsLostInFloatingPointIsRefusedNotCheckedForever) {
  // Found by fuzz_make_map: coordinates from 1e-308 to 1e8. Every step of the
  // composite is positive along the sample, but the product of their Jacobians
  // is not (floating point loses it), so no step is split; the composite check
  // used to repeat the same steps forever.
  MapSpec spec;
  spec.type = "composite_mean_value";
  spec.coordinates = "mean_value";
  spec.vertex_path = "linear";
  spec.partition = "adaptive";
  spec.steps = 1;
  spec.times = {0, 1};
  spec.sample_resolution = 8;
  spec.min_interval = 1e-2;
  spec.max_steps = 16;
  spec.source = Polygon({Point<2>(0x1.0000001p-1017, 0x1p-623), Point<2>(0x1p-383, 0),
                         Point<2>(0x1p-383, -0x1.4p-15), Point<2>(0x1.00000013p+0, 0x1.5p-1008)},
                        "source polygon");
  spec.target = Polygon({Point<2>(0, 0), Point<2>(0x0.00000c197d784p-1022, -0x1.7d78400fp+26),
                         Point<2>(1, 0x0.000000000008cp-1022), Point<2>(0, 0x0.0c01ap-1022)},
                        "target polygon");
  try {
    const MapPtr<2> f = make_map(spec);
    Points<2> x0(1, 2), x;
    x0 << 0.5, -1e-6;
    f->eval(x0, x);
    EXPECT_TRUE(x.allFinite());
  } catch (const Error& e) {
    EXPECT_FALSE(e.context().hint.empty()) << e.what();
  }
}

}  // namespace
}  // namespace warpfem::mapping
