#include "io/expression.hpp"

#include <muParser.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "fem/functions.hpp"

namespace warpfem::io {

struct Expression::Impl {
  mu::Parser parser;
  mutable double x = 0, y = 0, z = 0, t = 0;
};

Expression::Expression(const std::string& text, const std::string& file, const std::string& key_path)
    : impl_(std::make_unique<Impl>()), text_(text), file_(file), key_path_(key_path) {
  try {
    mu::Parser& p = impl_->parser;
    p.DefineConst("pi", std::numbers::pi);
    p.DefineConst("e", std::numbers::e);
    p.DefineVar("x", &impl_->x);
    p.DefineVar("y", &impl_->y);
    p.DefineVar("z", &impl_->z);
    p.DefineVar("t", &impl_->t);
    p.SetExpr(text);
    const double value = p.Eval();  // forces parsing now, so errors surface at load time
    constant_ = p.GetUsedVar().empty();
    if (constant_ && !std::isfinite(value))
      throw Error("expression \"" + text + "\" is not a finite number",
                  {.file = file, .key_path = key_path, .hint = "check for division by zero"});
  } catch (const mu::Parser::exception_type& e) {
    throw Error("cannot parse expression \"" + text + "\": " + e.GetMsg(),
                {.file = file,
                 .key_path = key_path,
                 .hint = "use the variables x, y, z, t, the constants pi and e, and functions such as sin, "
                         "exp, sqrt, abs, ^ for powers"});
  }
}

Expression::Expression(const Expression& other) : Expression(other.text_, other.file_, other.key_path_) {}

Expression::~Expression() = default;

double Expression::operator()(double x, double y, double z, double t) const {
  impl_->x = x;
  impl_->y = y;
  impl_->z = z;
  impl_->t = t;
  try {
    return impl_->parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw Error("cannot evaluate expression \"" + text_ + "\": " + e.GetMsg(),
                {.file = file_, .key_path = key_path_, .hint = ""});
  }
}

std::function<double(const Point<2>&, double)> Expression::as_function_2d() const {
  if (constant_) return fem::ConstantFunction{(*this)(0.0, 0.0)};  // recognisable, no parser per point
  auto copy = std::make_shared<Expression>(*this);
  return [copy](const Point<2>& p, double t) { return (*copy)(p(0), p(1), 0.0, t); };
}

}  // namespace warpfem::io
