// Composite harmonic maps f = φ1⁻¹ ∘ φ0 (thesis eq. 5.2, §5.2): the inverse,
// Jacobians, boundary behaviour and bijectivity where one mean value step folds.

#include <gtest/gtest.h>

#include <cstdio>

#include "core/error.hpp"
#include "harmonic_test_utils.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/distortion.hpp"
#include "mapping/harmonic/intermediate_polygon.hpp"
#include "mapping/harmonic/make_harmonic_map.hpp"
#include "mapping/make_map.hpp"
#include "mapping/map_check.hpp"
#include "mapping/polygon_sampling.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

CompositeHarmonicMap composite(const Polygon& from, const Polygon& to, HarmonicMethod method,
                               Index nodes = 256) {
  HarmonicOptions o;
  o.method = method;
  o.boundary_nodes = nodes;
  const Polygon L = regular_polygon(from.size());
  return CompositeHarmonicMap(make_harmonic(from, L, {}, o), make_harmonic(to, L, {}, o));
}

const HarmonicMethod kMethods[] = {HarmonicMethod::fem, HarmonicMethod::bem, HarmonicMethod::mfs};

TEST(CompositeHarmonicMap, BijectiveWhereOneMeanValueStepFoldsOrReportsWhyNot) {
  const Polygon from = test::diamond(), to = test::dart();
  const Points<2> sample = bijectivity_sample(from, 64);
  ASSERT_LT(min_det_jacobian(BarycentricMap(from, to), sample), 0.0);  // thesis §2.1.2
  for (HarmonicMethod method : kMethods) {
    const CompositeHarmonicMap f = composite(from, to, method);
    const MapCheck check = check_map(f, sample);
    std::printf("[ diamond -> dart ] %s: %s; %ld failed inverses, %ld det <= 0\n", to_string(method).c_str(),
                check.summary().c_str(), static_cast<long>(check.failed_inverse),
                static_cast<long>(check.nonpositive));
    if (method == HarmonicMethod::fem) {
      EXPECT_TRUE(check.passed());
    }
    // The plain evaluation refuses exactly when the check counts failed inverses.
    bool threw = false;
    try {
      Jacobians<2> J;
      f.jacobian(sample, J);
    } catch (const Error& e) {
      threw = true;
      EXPECT_NE(std::string(e.what()).find("does not converge at x0"), std::string::npos) << e.what();
    }
    EXPECT_EQ(threw, check.failed_inverse > 0) << to_string(method);
    // vertices go to vertices wherever the inverse converged
    Points<2> v(from.size(), 2), fv;
    for (Index i = 0; i < from.size(); ++i) v.row(i) = from.vertex(i).transpose();
    Jacobians<2> Jv;
    VectorX residual;
    f.eval_with_residual(v, fv, Jv, residual);
    for (Index i = 0; i < from.size(); ++i) {
      if (residual(i) > f.inverse_tolerance()) continue;
      EXPECT_LT((fv.row(i).transpose() - to.vertex(i)).norm(), 1e-9) << to_string(method) << " vertex " << i;
    }
  }
}

TEST(CompositeHarmonicMap, FemMapsEdgesLinearlyOntoEdges) {
  const Polygon from = test::star(), to = test::star(0.5);
  const CompositeHarmonicMap f = composite(from, to, HarmonicMethod::fem);
  Points<2> x(from.size() * 7, 2), fx;
  for (Index i = 0; i < from.size(); ++i)
    for (int k = 0; k < 7; ++k)
      x.row(7 * i + k) = ((1 - k / 7.0) * from.vertex(i) + (k / 7.0) * from.vertex(i + 1)).transpose();
  f.eval(x, fx);
  for (Index i = 0; i < from.size(); ++i)
    for (int k = 0; k < 7; ++k) {
      const Point<2> expected = (1 - k / 7.0) * to.vertex(i) + (k / 7.0) * to.vertex(i + 1);
      EXPECT_LT((fx.row(7 * i + k).transpose() - expected).norm(), 1e-12) << "edge " << i << " k " << k;
    }
}

TEST(CompositeHarmonicMap, InverseComposesToTheIdentity) {
  const Polygon from = test::star(), to = test::star(0.5);
  const Points<2> x = grid_sample(from, 16);
  for (HarmonicMethod method : kMethods) {
    const CompositeHarmonicMap f = composite(from, to, method, 200);
    const CompositeHarmonicMap g = f.inverse();
    Points<2> y, back;
    f.eval(x, y);
    g.eval(y, back);
    const Real err = (back - x).rowwise().norm().maxCoeff();
    std::printf("[ round trip ] %s: max |f^-1(f(x)) - x| = %.2e\n", to_string(method).c_str(), err);
    EXPECT_LT(err, 1e-9) << to_string(method);
  }
}

TEST(CompositeHarmonicMap, JacobianMatchesCentralDifferences) {
  const Polygon from = test::diamond(), to = test::dart();
  // bem takes J_φ a quarter element inside when closer to ∂Ω, so test where
  // both x and f(x) are away from the boundary
  const Points<2> x0 = test::keep_away_from_boundary(grid_sample(from, 12), from, 0.05);
  for (HarmonicMethod method : {HarmonicMethod::bem, HarmonicMethod::mfs}) {
    const CompositeHarmonicMap f = composite(from, to, method, 128);
    Points<2> y;
    f.eval(x0, y);
    const Points<2> y_in = test::keep_away_from_boundary(y, to, 0.03);
    Points<2> x(y_in.rows(), 2);
    f.inverse().eval(y_in, x);
    ASSERT_GT(x.rows(), 10);
    EXPECT_LT(test::jacobian_fd_error(f, x, 1e-6), 1e-5) << to_string(method);
  }
}

TEST(CompositeHarmonicMap, IdenticalPolygonsGiveTheIdentity) {
  // mfs: φ(Ω) is not exactly Λ next to ∂Ω, so stay a little inside
  const Polygon P = test::concave32();
  const Points<2> x = test::keep_away_from_boundary(grid_sample(P, 16), P, 0.05);
  for (HarmonicMethod method : kMethods) {
    Points<2> y;
    composite(P, P, method, 256).eval(x, y);
    EXPECT_LT((y - x).cwiseAbs().maxCoeff(), 1e-9) << to_string(method);
  }
}

TEST(MakeHarmonicMap, BuildsFromASpecAndNamesBadFields) {
  MapSpec spec;
  spec.type = "composite_harmonic";
  spec.source = test::diamond();
  spec.target = test::dart();
  spec.origin = "spec.json";
  for (const char* inter : {"regular", "cyclic", "optimized"}) {
    spec.intermediate = inter;
    const auto f = make_composite_harmonic(spec);
    EXPECT_GT(min_det_jacobian(*f, bijectivity_sample(*spec.source, 32)), 0.0) << inter;
    EXPECT_NE(f->describe().find("composite harmonic (fem)"), std::string::npos) << f->describe();
  }
  auto expect_key = [&](MapSpec s, const std::string& key) {
    try {
      make_harmonic_map(s);
      FAIL() << "expected an error at " << key;
    } catch (const Error& e) {
      EXPECT_EQ(e.context().key_path, key) << e.what();
      EXPECT_EQ(e.context().file, "spec.json") << e.what();
    }
  };
  MapSpec bad = spec;
  bad.harmonic_method = "fdm";
  expect_key(bad, "map.harmonic_method");
  bad = spec;
  bad.intermediate = "square";
  expect_key(bad, "map.intermediate");
  bad = spec;
  bad.boundary_nodes = 2;
  expect_key(bad, "map.boundary_nodes");
  bad = spec;
  bad.target_edge_speeds = {"linear", "cubic", "linear", "linear"};
  expect_key(bad, "map.target_edge_speeds");
  bad = spec;
  bad.source_edge_speeds = {"linear"};
  expect_key(bad, "map.source_edge_speeds");
  bad = spec;
  bad.target = test::star();
  expect_key(bad, "map.target");
}

TEST(MakeHarmonicMap, ShippedExamplesAreBijectiveOrRefused) {
  for (const char* name :
       {"harmonic_square_to_dart", "harmonic_star_to_bent_star", "harmonic_square_to_gear"}) {
    const MapSpec spec = test::load_harmonic_example(name);
    try {
      const auto f = make_map(spec);
      const Real det = min_det_jacobian(*f, bijectivity_sample(*spec.source, 48));
      std::printf("[ %s ] %s: min det J = %.3g\n", name, f->describe().c_str(), det);
      EXPECT_GT(det, 0.0) << name;
    } catch (const Error& e) {
      // only the smooth methods may be refused: their φ1 misses ∂Λ
      std::printf("[ %s ] refused: %s\n", name, e.what());
      EXPECT_NE(spec.harmonic_method, "fem") << e.what();
      EXPECT_NE(std::string(e.what()).find("\"harmonic_method\": \"fem\""), std::string::npos) << e.what();
    }
  }
}

TEST(CompositeHarmonicMap, QuadraticSpeedMovesBoundaryPointsAsPrescribed) {
  // thesis §5.4: edge i of Ω1 is traversed with speed t², so f maps the point at
  // parameter t of a source edge to the point at parameter sqrt(t) of the target edge
  const Polygon from = test::diamond(), to = test::dart(), L = regular_polygon(4);
  const std::vector<EdgeSpeed> quad(4, EdgeSpeed::quadratic);
  HarmonicOptions o;
  const CompositeHarmonicMap f(make_harmonic(from, L, {}, o), make_harmonic(to, L, quad, o));
  Points<2> x(1, 2), y;
  for (Index i = 0; i < 4; ++i) {
    x.row(0) = (0.75 * from.vertex(i) + 0.25 * from.vertex(i + 1)).transpose();
    f.eval(x, y);
    const Point<2> expected = 0.5 * to.vertex(i) + 0.5 * to.vertex(i + 1);  // sqrt(0.25)
    EXPECT_LT((y.row(0).transpose() - expected).norm(), 1e-3) << "edge " << i;
  }
}

}  // namespace
}  // namespace warpfem::mapping
