#pragma once
// The Poisson integrands as a cell kernel of integrate_cells (any dim):
// element matrix K_ab = ∫ ∇φa·∇φb dx and load F_a = ∫ g φa dx from the
// physical shape gradients of CellValues (update_gradients). end() hands the
// cell's (K, F) to `scatter`. PoissonProblem's 2D assembly folds J^{-T} into
// a metric instead (its fast path); this is the general form.

#include <functional>
#include <vector>

#include "fem/values/cell_values.hpp"

namespace warpfem::fem {

template <int dim>
class PoissonKernel {
 public:
  using Source = std::function<double(const Point<dim>& x)>;
  using Scatter = std::function<void(const CellValues<dim>& values, const double* ke, const double* fe)>;

  PoissonKernel(Source source, Scatter scatter) : source_(std::move(source)), scatter_(std::move(scatter)) {}

  bool begin(const CellValues<dim>& v) {
    const auto n = static_cast<std::size_t>(v.num_dofs());
    ke_.assign(n * n, 0.0);
    fe_.assign(n, 0.0);
    return true;
  }
  void point(const CellValues<dim>& v, Index q) {
    const int n = v.num_dofs();
    const auto grads = v.shape_gradients(q);
    const double w = v.JxW(q), g = w * source_(v.point(q));
    for (int a = 0; a < n; ++a) {
      fe_[static_cast<std::size_t>(a)] += g * v.shape_value(q, a);
      for (int b = 0; b < n; ++b)
        ke_[static_cast<std::size_t>(a * n + b)] += w * grads.col(a).dot(grads.col(b));
    }
  }
  void end(const CellValues<dim>& v) { scatter_(v, ke_.data(), fe_.data()); }

 private:
  Source source_;
  Scatter scatter_;
  std::vector<double> ke_, fe_;
};

}  // namespace warpfem::fem
