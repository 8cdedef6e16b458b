#pragma once
// The one geometry interface: a smooth bijective map f: Ω0 → Ω1, evaluated
// for batches of points (structure-of-arrays, see core/types.hpp).

#include <memory>
#include <string>

#include "core/types.hpp"

namespace warpfem::mapping {

template <int dim>
class Map {
 public:
  virtual ~Map() = default;

  /// x.row(p) = f(x0.row(p)) for every point p of the batch.
  virtual void eval(const Points<dim>& x0, Points<dim>& x) const = 0;

  /// J.row(p) = J_f(x0.row(p)), stored row-major per point (see Jacobians).
  virtual void jacobian(const Points<dim>& x0, Jacobians<dim>& J) const = 0;

  /// Values and Jacobians together; composite maps override this to share work.
  virtual void eval_with_jacobian(const Points<dim>& x0, Points<dim>& x, Jacobians<dim>& J) const {
    eval(x0, x);
    jacobian(x0, J);
  }

  /// Like eval_with_jacobian, and residual(p) = |g(y) − z| of the inverse that f
  /// solves to evaluate at point p (0 for maps that solve none). A point with
  /// residual(p) > inverse_tolerance() is a failed evaluation: its x and J are
  /// not f there. Unlike eval(), this does not throw for such points, so a check
  /// can count them.
  virtual void eval_with_residual(const Points<dim>& x0, Points<dim>& x, Jacobians<dim>& J,
                                  VectorX& residual) const {
    eval_with_jacobian(x0, x, J);
    residual.setZero(x0.rows());
  }

  /// Largest inverse residual of a successful evaluation (absolute, in the
  /// units of the inverted map's image; 0 for maps that solve no inverse).
  virtual Real inverse_tolerance() const { return 0; }

  /// One line describing the map for logs ("identity", "composite mean value, 12 steps", ...).
  virtual std::string describe() const = 0;

  /// True if f is affine (then J_f is constant and P2 geometry is exact).
  virtual bool is_affine() const { return false; }
};

/// f(x) = x.
template <int dim>
class IdentityMap final : public Map<dim> {
 public:
  void eval(const Points<dim>& x0, Points<dim>& x) const override { x = x0; }
  void jacobian(const Points<dim>& x0, Jacobians<dim>& J) const override {
    J.setZero(x0.rows(), dim * dim);
    for (int i = 0; i < dim; ++i) J.col(i * dim + i).setOnes();
  }
  std::string describe() const override { return "identity"; }
  bool is_affine() const override { return true; }
};

template <int dim>
using MapPtr = std::shared_ptr<const Map<dim>>;

}  // namespace warpfem::mapping
