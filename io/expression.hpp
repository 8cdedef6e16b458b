#pragma once
// Scalar expressions of x, y, z, t (with the constants pi and e) from config
// files, parsed by muParser. Example: "sin(pi*x)*exp(-t) + y^2".

#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "core/types.hpp"

namespace warpfem::io {

class Expression {
 public:
  /// Parses `text`; throws warpfem::Error naming `file` and `key_path` with
  /// muParser's diagnosis (unknown variable, unbalanced parenthesis, ...).
  Expression(const std::string& text, const std::string& file = "", const std::string& key_path = "");
  ~Expression();
  Expression(const Expression& other);
  Expression& operator=(const Expression&) = delete;

  double operator()(double x, double y, double z = 0.0, double t = 0.0) const;
  template <int dim>
  double at(const Point<dim>& p, double t = 0.0) const {
    double c[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < dim; ++i) c[i] = p(i);
    return (*this)(c[0], c[1], c[2], t);
  }
  /// Central-difference gradient in x, y (, z): for H1 error norms when only u is given.
  template <int dim>
  Point<dim> gradient(const Point<dim>& p, double t = 0.0) const {
    Point<dim> g;
    for (int i = 0; i < dim; ++i) {
      const double h = 1e-5 * (1.0 + std::abs(p(i)));
      Point<dim> a = p, b = p;
      a(i) += h;
      b(i) -= h;
      g(i) = (at<dim>(a, t) - at<dim>(b, t)) / (2 * h);
    }
    return g;
  }

  /// True if the text is a plain constant (no variables used).
  bool is_constant() const { return constant_; }
  const std::string& text() const { return text_; }

  /// A std::function view (shares this expression's parser; copy the Expression first if it may die).
  std::function<double(const Point<2>&, double)> as_function_2d() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string text_, file_, key_path_;
  bool constant_ = false;
};

}  // namespace warpfem::io
