#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "fem/physics/functions.hpp"
#include "io/expression.hpp"

using warpfem::Error;
using warpfem::io::Expression;

TEST(Expression, EvaluatesVariablesAndConstants) {
  const Expression e("sin(pi*x)*cos(y) + z^2 - t/2");
  EXPECT_NEAR(e(0.25, 0.5, 3.0, 4.0), std::sin(std::numbers::pi * 0.25) * std::cos(0.5) + 9.0 - 2.0, 1e-14);
  EXPECT_FALSE(e.is_constant());
  const Expression c("2*pi");
  EXPECT_TRUE(c.is_constant());
  EXPECT_NEAR(c(9, 9), 2 * std::numbers::pi, 1e-15);
}

// A constant expression becomes a recognisable fem::ConstantFunction (assembly
// then skips the per-point calls); any other one stays a pointwise function.
TEST(Expression, ConstantExpressionsBecomeConstantFunctions) {
  const auto c = Expression("3*pi/2").as_function_2d();
  const auto* constant = c.target<warpfem::fem::ConstantFunction>();
  ASSERT_NE(constant, nullptr);
  EXPECT_NEAR(constant->value, 1.5 * std::numbers::pi, 1e-15);
  EXPECT_NEAR(c(warpfem::Point<2>(7, -3), 2.0), 1.5 * std::numbers::pi, 1e-15);
  const auto f = Expression("x + 2*y - t").as_function_2d();
  EXPECT_EQ(f.target<warpfem::fem::ConstantFunction>(), nullptr);
  EXPECT_DOUBLE_EQ(f(warpfem::Point<2>(1, 2), 3.0), 2.0);
}

TEST(Expression, CopiesAreIndependent) {
  const Expression a("x + 1");
  const Expression b(a);
  EXPECT_DOUBLE_EQ(a(1, 0), 2.0);
  EXPECT_DOUBLE_EQ(b(5, 0), 6.0);
  EXPECT_DOUBLE_EQ(a(1, 0), 2.0);
}

TEST(Expression, GradientMatchesAnalytic) {
  const Expression e("x^2*y + sin(y)");
  const warpfem::Point<2> p(0.3, 0.7);
  const auto g = e.gradient<2>(p);
  EXPECT_NEAR(g(0), 2 * 0.3 * 0.7, 1e-8);
  EXPECT_NEAR(g(1), 0.09 + std::cos(0.7), 1e-8);
}

TEST(Expression, SyntaxErrorsNameFileAndField) {
  try {
    Expression("2 * (x + ", "run.json", "/problem/source");
    FAIL();
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("run.json: /problem/source: cannot parse expression", 0), 0u) << m;
  }
  EXPECT_THROW(Expression("foo(x)"), Error);
  EXPECT_THROW(Expression("x + q"), Error);
  EXPECT_THROW(Expression(""), Error);
}

TEST(Expression, ConstantDivisionByZeroIsRejected) {
  EXPECT_THROW(Expression("1/0"), Error);
}
