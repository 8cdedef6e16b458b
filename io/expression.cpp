#include "io/expression.hpp"

#include <muParser.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "fem/physics/functions.hpp"

namespace warpfem::io {

namespace {

/// muParser accepts "x=3" (an assignment to the variable x) as an expression
/// whose value is 3: a "=" that is not part of ==, <=, >= or != is refused.
bool has_assignment(const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '=') continue;
    const char before = i > 0 ? text[i - 1] : ' ';
    const char after = i + 1 < text.size() ? text[i + 1] : ' ';
    if (after == '=') {
      ++i;  // "==": skip both
      continue;
    }
    if (before != '<' && before != '>' && before != '!') return true;
  }
  return false;
}

}  // namespace

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
    if (has_assignment(text))
      throw Error("expression \"" + text + "\" assigns a value (\"=\"): an expression only computes one",
                  {.file = file,
                   .key_path = key_path,
                   .hint = "write the value itself, e.g. \"3\" for x=3; compare with \"==\""});
    p.SetExpr(text);
    const double value = p.Eval();  // forces parsing now, so errors surface at load time
    if (p.GetNumResults() != 1)
      throw Error(
          "expression \"" + text + "\" is a list of " + std::to_string(p.GetNumResults()) +
              " values (commas separate them): one value is needed",
          {.file = file, .key_path = key_path, .hint = "give a single expression without top-level commas"});
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
