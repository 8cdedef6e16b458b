// The adaptive interpolant of a composite mean value map (mapping/adaptive_interpolant.hpp)
// against exact evaluation: accuracy at random points and near vertices and edges,
// batched = pointwise, exact behaviour outside Ω0, and an unchanged Poisson solve.

#include <gtest/gtest.h>

#include <random>

#include "apps/convergence_study.hpp"
#include "mapping/adaptive_interpolant.hpp"
#include "mapping/make_map.hpp"
#include "test_polygons.hpp"

using namespace warpfem;
using namespace warpfem::mapping;
using namespace warpfem::mapping::test;

namespace {

struct Gear {
  MapSpec spec = load_example("square_to_gear");
  MapPtr<2> exact = make_map(spec);
  std::shared_ptr<const AdaptiveInterpolant> interp =
      std::make_shared<AdaptiveInterpolant>(exact, *spec.source);
  Real diam = (spec.source->bbox_max() - spec.source->bbox_min()).norm();
};

const Gear& gear() {
  static const Gear g;
  return g;
}

// Random points of Ω0, then points 1e-3 … 1e-9 · diam from every vertex and
// edge midpoint (inside), and the edge midpoints themselves.
Points<2> probe_points(const Polygon& p, Real diam) {
  std::vector<Point<2>> pts;
  std::mt19937_64 rng(3);
  const Point<2> lo = p.bbox_min(), hi = p.bbox_max();
  std::uniform_real_distribution<Real> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  while (pts.size() < 4000) {
    const Point<2> q(ux(rng), uy(rng));
    if (p.side_of(q) > 0) pts.push_back(q);
  }
  for (Index i = 0; i < p.size(); ++i) {
    const Point<2> a = p.vertex(i), b = p.vertex(i + 1), c = p.vertex(i - 1);
    const Point<2> along = (b - a).normalized(), back = (c - a).normalized();
    const Point<2> normal(-along.y(), along.x());  // counter-clockwise: inward
    for (Real d : {1e-3, 1e-5, 1e-7, 1e-9}) {
      const Point<2> v =
          a + d * diam * (along + back).normalized() * (p.side_of(a + 1e-9 * (along + back)) > 0 ? 1 : -1);
      if (p.side_of(v) > 0) pts.push_back(v);
      pts.push_back((a + b) / 2 + d * diam * normal);
    }
    pts.push_back((a + b) / 2);
  }
  Points<2> x(static_cast<Index>(pts.size()), 2);
  for (std::size_t k = 0; k < pts.size(); ++k) x.row(static_cast<Index>(k)) = pts[k].transpose();
  return x;
}

TEST(MapInterpolant, MatchesExactMapWithinTheTolerance) {
  const Gear& g = gear();
  const Points<2> x = probe_points(*g.spec.source, g.diam);
  Points<2> fe, fi;
  Jacobians<2> Je, Ji;
  g.exact->eval_with_jacobian(x, fe, Je);
  g.interp->eval_with_jacobian(x, fi, Ji);
  const Real tol = g.interp->options().tolerance;
  Real worst_f = 0, worst_J = 0;
  for (Index p = 0; p < x.rows(); ++p) {
    worst_f = std::max(worst_f, (fi.row(p) - fe.row(p)).lpNorm<Eigen::Infinity>() / g.diam);
    worst_J = std::max(
        worst_J, (Ji.row(p) - Je.row(p)).lpNorm<Eigen::Infinity>() / Je.row(p).lpNorm<Eigen::Infinity>());
  }
  std::printf("%lld points: worst f error %.2e · diam, J error %.2e relative\n",
              static_cast<long long>(x.rows()), worst_f, worst_J);
  EXPECT_LE(worst_f, tol);
  EXPECT_LE(worst_J, 1000 * tol);
  // Most of Ω0 is interpolated, not handed back to the exact map.
  const InterpolantStats& st = g.interp->stats();
  EXPECT_GT(st.interpolated_leaves, 0);
  EXPECT_LT(st.exact_area_fraction, 0.05);
}

TEST(MapInterpolant, BatchedEqualsPointwiseAndAllEntryPointsAgree) {
  const Gear& g = gear();
  const Points<2> x = probe_points(*g.spec.source, g.diam).topRows(300);
  Points<2> f, f_only;
  Jacobians<2> J, J_only;
  g.interp->eval_with_jacobian(x, f, J);
  g.interp->eval(x, f_only);
  g.interp->jacobian(x, J_only);
  // Points left to the exact map may differ in the last bits between its
  // value-only and value-and-Jacobian kernels.
  EXPECT_LE((f - f_only).lpNorm<Eigen::Infinity>(), 1e-15 * g.diam);
  EXPECT_LE((J - J_only).lpNorm<Eigen::Infinity>(), 1e-13 * J.lpNorm<Eigen::Infinity>());
  for (Index p = 0; p < x.rows(); ++p) {
    const Points<2> one = x.row(p);
    Points<2> f1;
    Jacobians<2> J1;
    g.interp->eval_with_jacobian(one, f1, J1);
    // The polynomial path is the same code per point; the exact path may vectorize differently.
    EXPECT_LE((f1.row(0) - f.row(p)).lpNorm<Eigen::Infinity>(), 1e-15 * g.diam) << "point " << p;
    EXPECT_LE((J1.row(0) - J.row(p)).lpNorm<Eigen::Infinity>(), 1e-13 * J.row(p).lpNorm<Eigen::Infinity>());
  }
  Points<2> in_place = x;  // x and f(x) in the same batch
  g.interp->eval(in_place, in_place);
  EXPECT_EQ(in_place, f_only);
}

TEST(MapInterpolant, PointsOutsideTheSourceAreEvaluatedByTheExactMap) {
  const Gear& g = gear();
  const Polygon& s = *g.spec.source;
  std::vector<Point<2>> out;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> u(-2, 2);
  while (out.size() < 500) {
    const Point<2> q(u(rng), u(rng));
    if (s.side_of(q) < 0) out.push_back(q);
  }
  for (Index i = 0; i < s.size(); ++i) {  // just outside the edges
    const Point<2> a = s.vertex(i), b = s.vertex(i + 1);
    const Point<2> t = (b - a).normalized();
    out.push_back((a + b) / 2 + 1e-9 * Point<2>(t.y(), -t.x()));
  }
  Points<2> x(static_cast<Index>(out.size()), 2);
  for (std::size_t k = 0; k < out.size(); ++k) x.row(static_cast<Index>(k)) = out[k].transpose();
  Points<2> fe, fi;
  Jacobians<2> Je, Ji;
  g.exact->eval_with_jacobian(x, fe, Je);
  g.interp->eval_with_jacobian(x, fi, Ji);
  for (Index p = 0; p < x.rows(); ++p) {
    EXPECT_EQ(fi.row(p), fe.row(p)) << "point " << p << " (" << x(p, 0) << ", " << x(p, 1) << ")";
    EXPECT_EQ(Ji.row(p), Je.row(p)) << "point " << p;
  }
}

TEST(MapInterpolant, MakeMapInterpolatesOnRequestAndChecksTheExactMap) {
  MapSpec spec = load_example("square_to_gear");
  MapCheck exact_check, interp_check;
  const MapPtr<2> exact = make_map(spec, &exact_check);
  spec.evaluation = "interpolated";
  spec.interpolation_tolerance = 1e-8;  // a quick build; accuracy is tested above
  const MapPtr<2> interp = make_map(spec, &interp_check);
  EXPECT_NE(interp->describe().find("interpolated"), std::string::npos);
  EXPECT_EQ(exact->describe().find("interpolated"), std::string::npos);
  EXPECT_EQ(interp_check.min_det, exact_check.min_det);
  spec.evaluation = "fast";
  EXPECT_THROW(make_map(spec), Error);
  spec.evaluation = "interpolated";
  spec.interpolation_tolerance = -1;
  EXPECT_THROW(make_map(spec), Error);
}

TEST(MapInterpolant, AutoInterpolatesOnlyWhereTheRunIsLargeEnough) {
  MapSpec spec = load_example("square_to_gear");  // 7 steps of 40 vertices: 280 vertex terms per point
  spec.interpolation_tolerance = 1e-8;            // a quick build
  const auto interpolated = [&spec] {
    return make_map(spec)->describe().find("interpolated") != std::string::npos;
  };
  ASSERT_EQ(spec.evaluation, "auto");
  spec.evaluation_points = 0;  // unknown (warpfem map, warp-image): exact
  EXPECT_FALSE(interpolated());
  spec.evaluation_points = 1e5;  // the build would cost more than it saves
  EXPECT_FALSE(interpolated());
  spec.evaluation_points = 1e7;
  EXPECT_TRUE(interpolated());
  spec.evaluation = "exact";
  EXPECT_FALSE(interpolated());

  // The run's config reader estimates the finest level's quadrature points:
  // 4 times more per refinement, 3 per triangle for P1 (degree 2) and 6 for P2 (degree 4).
  nlohmann::json j =
      io::ConfigNode::parse_file(std::string(WARPFEM_SOURCE_DIR) + "/examples/poisson_gear_curved.json");
  const auto points = [&j](int order, int refinements) {
    j["problem"]["order"] = order;
    j["mesh"]["refinements"] = refinements;
    return io::parse_run_config(j, "gear.json").map.evaluation_points;
  };
  const double p1 = points(1, 2);
  EXPECT_GT(p1, 0);
  EXPECT_DOUBLE_EQ(points(1, 3), 4 * p1);
  EXPECT_DOUBLE_EQ(points(2, 2), 2 * p1);
}

TEST(MapInterpolant, PoissonOnTheGearIsUnchanged) {
  // u = sin(2x) cos(y) + x² on the gear, P2, three levels: errors and CG iterations.
  auto run = [](const std::string& evaluation) {
    const std::string file = std::string(WARPFEM_SOURCE_DIR) + "/examples/maps/square_to_gear.json";
    nlohmann::json j = nlohmann::json::parse(R"json({
      "verbosity": "warning",
      "mesh": {"type": "structured", "cells": [4, 4]},
      "problem": {"order": 2, "source": "5*sin(2*x)*cos(y) - 2",
                  "dirichlet": [{"value": "sin(2*x)*cos(y) + x^2"}],
                  "exact_solution": "sin(2*x)*cos(y) + x^2"}})json");
    j["map"] = io::ConfigNode::parse_file(file)["map"];
    j["map"]["evaluation"] = evaluation;
    const io::RunConfig cfg = io::parse_run_config(j, "test.json");
    apps::StudySpec spec;
    spec.levels = 3;
    spec.discretizations = {"warped"};
    spec.plot = false;
    return apps::run_study(cfg, spec, MPI_COMM_SELF, false).rows;
  };
  const auto exact = run("exact");
  const auto interp = run("interpolated");
  ASSERT_EQ(exact.size(), interp.size());
  for (std::size_t k = 0; k < exact.size(); ++k) {
    std::printf("level %d: L2 %.12e vs %.12e, H1 %.12e vs %.12e, iterations %d vs %d\n", exact[k].level,
                exact[k].l2, interp[k].l2, exact[k].h1, interp[k].h1, exact[k].iterations,
                interp[k].iterations);
    EXPECT_NEAR(interp[k].l2, exact[k].l2, 1e-8 * exact[k].l2);
    EXPECT_NEAR(interp[k].h1, exact[k].h1, 1e-8 * exact[k].h1);
    EXPECT_NEAR(interp[k].area, exact[k].area, 1e-11 * exact[k].area);
    EXPECT_EQ(interp[k].iterations, exact[k].iterations);
  }
}

}  // namespace
