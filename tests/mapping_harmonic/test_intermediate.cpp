// Intermediate polygons Λ (thesis §5.3): regular, cyclic, optimized.

#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>

#include "core/error.hpp"
#include "mapping/harmonic/intermediate_optimizer.hpp"
#include "mapping/harmonic/intermediate_polygon.hpp"
#include "test_polygons.hpp"

namespace warpfem::mapping {
namespace {

TEST(IntermediatePolygon, RegularAndCyclicAreConvexWithTheRightEdges) {
  for (Index n : {3, 4, 10, 40}) EXPECT_TRUE(regular_polygon(n).is_convex());
  // center inside and center outside the cyclic polygon
  for (const std::vector<Real>& l : {std::vector<Real>{1, 2, 1.5, 1, 0.7}, std::vector<Real>{3, 1, 1, 1.2}}) {
    const Polygon C = cyclic_polygon(l);
    C.validate();
    EXPECT_TRUE(is_strictly_convex(C.vertices()));
    const Real R = C.vertex(0).norm();
    for (Index i = 0; i < C.size(); ++i) {
      EXPECT_NEAR((C.vertex(i + 1) - C.vertex(i)).norm(), l[static_cast<std::size_t>(i)], 1e-12);
      EXPECT_NEAR(C.vertex(i).norm(), R, 1e-12);
    }
  }
  EXPECT_THROW(cyclic_polygon({1, 1, 3}), Error);
  const Polygon avg = cyclic_intermediate(test::diamond(), test::dart());
  EXPECT_TRUE(is_strictly_convex(avg.vertices()));
  EXPECT_FALSE(is_strictly_convex(test::dart().vertices()));
  EXPECT_FALSE(is_strictly_convex({{0, 0}, {1, 0}, {2, 0}, {1, 1}}));
}

TEST(IntermediateOptimizer, ReducesTheDistortionAndKeepsLambdaConvex) {
  HarmonicOptions o;
  o.method = HarmonicMethod::fem;
  const Polygon L = regular_polygon(4);
  const auto phi0 = make_harmonic(test::diamond(), L, {}, o);
  const auto phi1 = make_harmonic(test::dart(), L, {}, o);
  for (const char* energy : {"conformal", "isometric"}) {
    const IntermediateOptimization r = optimize_intermediate(phi0, phi1, {.energy = energy, .sweeps = 3});
    std::printf("[ optimize %s ] energy %.4f -> %.4f in %d evaluations; min det %.3g -> %.3g\n", energy,
                r.energy_before, r.energy_after, r.energy_evaluations, r.before.min_det, r.after.min_det);
    EXPECT_LT(r.energy_after, r.energy_before * 0.999) << energy;
    EXPECT_TRUE(is_strictly_convex(r.polygon.vertices())) << energy;
    EXPECT_GT(r.after.min_det, 0.0);
  }
  EXPECT_THROW(optimize_intermediate(phi0, phi1, {.energy = "dirichlet"}), Error);
}

}  // namespace
}  // namespace warpfem::mapping
