#include <gtest/gtest.h>

#include <cmath>

#include "core/mesh/quadrature.hpp"
#include "fem/reference/lagrange_element.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {
// ∫ x^a y^b over the reference triangle = a! b! / (a + b + 2)!.
double triangle_monomial(int a, int b) {
  return std::tgamma(a + 1) * std::tgamma(b + 1) / std::tgamma(a + b + 3);
}
}  // namespace

TEST(Quadrature, GaussLegendreIsExactToDegree2nMinus1) {
  for (int n = 1; n <= 6; ++n) {
    const auto rule = gauss_legendre(n);
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double s = 0;
      for (Index q = 0; q < rule.size(); ++q) s += rule.weights(q) * std::pow(rule.points(q, 0), k);
      EXPECT_NEAR(s, 1.0 / (k + 1), 1e-14) << "n=" << n << " k=" << k;
    }
  }
}

TEST(Quadrature, GaussLegendreStaysAccurateForManyPoints) {
  // Up to the 64 points a boundary element panel may use.
  for (int n : {7, 12, 16, 24, 32, 48, 64}) {
    const auto rule = gauss_legendre(n);
    for (Index q = 0; q < n; ++q) {
      if (q > 0) {
        EXPECT_GT(rule.points(q, 0), rule.points(q - 1, 0)) << "n=" << n;
      }
      // The rule is symmetric about 1/2: asymmetry measures the error of the nodes and weights.
      EXPECT_NEAR(rule.points(q, 0) + rule.points(n - 1 - q, 0), 1.0, 4e-16) << "n=" << n << " q=" << q;
      EXPECT_NEAR(rule.weights(q) / rule.weights(n - 1 - q), 1.0, 1e-14) << "n=" << n << " q=" << q;
    }
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double s = 0;
      for (Index q = 0; q < rule.size(); ++q) s += rule.weights(q) * std::pow(rule.points(q, 0), k);
      EXPECT_NEAR(s * (k + 1), 1.0, 1e-13) << "n=" << n << " k=" << k;
    }
  }
}

TEST(Quadrature, TriangleRulesIntegrateMonomialsExactly) {
  for (int degree = 0; degree <= 10; ++degree) {
    const auto rule = cell_quadrature<2>(CellType::triangle, degree);
    EXPECT_GT(rule.weights.minCoeff(), 0.0);
    // Inside the cell: WarpedGeometry evaluates the map at these points.
    for (Index q = 0; q < rule.size(); ++q) {
      EXPECT_GT(rule.points(q, 0), 0.0) << "degree " << degree;
      EXPECT_GT(rule.points(q, 1), 0.0) << "degree " << degree;
      EXPECT_LT(rule.points(q, 0) + rule.points(q, 1), 1.0) << "degree " << degree;
    }
    for (int a = 0; a <= degree; ++a)
      for (int b = 0; a + b <= degree; ++b) {
        double s = 0;
        for (Index q = 0; q < rule.size(); ++q)
          s += rule.weights(q) * std::pow(rule.points(q, 0), a) * std::pow(rule.points(q, 1), b);
        EXPECT_NEAR(s, triangle_monomial(a, b), 1e-14) << "degree " << degree << " x^" << a << " y^" << b;
      }
  }
}

TEST(Quadrature, QuadrilateralRulesIntegrateTensorMonomials) {
  const auto rule = cell_quadrature<2>(CellType::quadrilateral, 5);
  for (int a = 0; a <= 5; ++a)
    for (int b = 0; b <= 5; ++b) {
      double s = 0;
      for (Index q = 0; q < rule.size(); ++q)
        s += rule.weights(q) * std::pow(rule.points(q, 0), a) * std::pow(rule.points(q, 1), b);
      EXPECT_NEAR(s, 1.0 / ((a + 1) * (b + 1)), 1e-14);
    }
}

class LagrangeElementTest : public ::testing::TestWithParam<std::pair<CellType, int>> {};

TEST_P(LagrangeElementTest, KroneckerPropertyPartitionOfUnityAndGradients) {
  const auto [type, order] = GetParam();
  const LagrangeElement<2> el(type, order);
  // Nodal (Kronecker) property.
  const MatrixX at_nodes = el.values(el.nodes());
  EXPECT_TRUE(at_nodes.isApprox(MatrixX::Identity(el.num_dofs(), el.num_dofs()), 1e-14));
  // Partition of unity, linear precision and gradients vs central differences at interior points.
  const auto rule = cell_quadrature<2>(type, 4);
  const MatrixX phi = el.values(rule.points);
  const auto grad = el.gradients(rule.points);
  for (Index q = 0; q < rule.size(); ++q) {
    EXPECT_NEAR(phi.row(q).sum(), 1.0, 1e-14);
    EXPECT_NEAR(phi.row(q).dot(el.nodes().col(0)), rule.points(q, 0), 1e-14);
    EXPECT_NEAR(phi.row(q).dot(el.nodes().col(1)), rule.points(q, 1), 1e-14);
    for (int d = 0; d < 2; ++d) {
      Points<2> plus = rule.points.row(q), minus = rule.points.row(q);
      plus(0, d) += 1e-6;
      minus(0, d) -= 1e-6;
      const MatrixX fd = (el.values(plus) - el.values(minus)) / 2e-6;
      for (int k = 0; k < el.num_dofs(); ++k) EXPECT_NEAR(grad[d](q, k), fd(0, k), 1e-8);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllElements, LagrangeElementTest,
                         ::testing::Values(std::make_pair(CellType::triangle, 1),
                                           std::make_pair(CellType::triangle, 2),
                                           std::make_pair(CellType::quadrilateral, 1),
                                           std::make_pair(CellType::quadrilateral, 2)));
