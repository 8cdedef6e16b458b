#pragma once
// Shared pieces of the 3D Poisson tests: maps of the unit cube (an affine one
// and a polynomial bijection that moves the boundary) and manufactured
// solutions with their data.

#include <Eigen/LU>
#include <cmath>
#include <memory>
#include <string>

#include "core/mesh/structured_mesher.hpp"
#include "fem/physics/poisson.hpp"
#include "mapping/map.hpp"

namespace warpfem::testing3d {

/// f(x0) = A x0 + b.
class AffineMap3 final : public mapping::Map<3> {
 public:
  AffineMap3(const Matrix<3>& A, const Point<3>& b) : A_(A), b_(b) {}
  void eval(const Points<3>& x0, Points<3>& x) const override {
    x = (x0 * A_.transpose()).rowwise() + b_.transpose();
  }
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override {
    J.resize(x0.rows(), 9);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) J.col(3 * r + c).setConstant(A_(r, c));
  }
  std::string describe() const override { return "affine"; }
  bool is_affine() const override { return true; }
  const Matrix<3>& matrix() const { return A_; }

 private:
  Matrix<3> A_;
  Point<3> b_;
};

/// A sheared, stretched cube: every face is a non-rectangular parallelogram.
inline std::shared_ptr<const AffineMap3> sheared_cube() {
  Matrix<3> A;
  A << 1.2, 0.3, -0.1, 0.1, 0.9, 0.25, -0.2, 0.15, 1.1;
  return std::make_shared<AffineMap3>(A, Point<3>(0.5, -0.3, 0.2));
}

/// f(x0) = (x + a y², y + a z², z + a x²): a smooth bijection of the unit cube
/// (|J − I| ≤ 2a < 1) whose image has curved faces.
class BentCube final : public mapping::Map<3> {
 public:
  static constexpr double a = 0.1;
  void eval(const Points<3>& x0, Points<3>& x) const override {
    x.resize(x0.rows(), 3);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double u = x0(p, 0), v = x0(p, 1), w = x0(p, 2);
      x(p, 0) = u + a * v * v, x(p, 1) = v + a * w * w, x(p, 2) = w + a * u * u;
    }
  }
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override {
    J.setZero(x0.rows(), 9);
    for (Index p = 0; p < x0.rows(); ++p) {
      J(p, 0) = J(p, 4) = J(p, 8) = 1;
      J(p, 1) = 2 * a * x0(p, 1), J(p, 5) = 2 * a * x0(p, 2), J(p, 6) = 2 * a * x0(p, 0);
    }
  }
  std::string describe() const override { return "bent cube"; }

  /// The outward unit normal of the image of the face x0 = 1 at its physical point x.
  static Point<3> normal_of_face_x1(const Point<3>& x) {
    const double w = x.z() - a;                          // z = w + a·1²
    const double v = x.y() - a * w * w;                  // y = v + a w²
    const Point<3> n(1, -2 * a * v, 4 * a * a * v * w);  // (J e_y) × (J e_z)
    return n.normalized();
  }
};

/// u = sin(x) cos(y) exp(z): −Δu = u.
inline double smooth_u(const Point<3>& x) {
  return std::sin(x.x()) * std::cos(x.y()) * std::exp(x.z());
}
inline Point<3> smooth_grad(const Point<3>& x) {
  const double s = std::sin(x.x()), c = std::cos(x.y()), e = std::exp(x.z());
  return {std::cos(x.x()) * c * e, -s * std::sin(x.y()) * e, s * c * e};
}

/// Box face tags of structured_box_mesh: 1 is x = 1.
inline constexpr int kFaceX1 = 1;

inline Mesh<3> unit_cube(int n, CellType type) {
  return structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), {n, n, n}, type);
}

/// −Δu = u, u = smooth_u, on the bent cube: u on five faces as Dirichlet
/// data, the exact flux ∂u/∂n on the curved image of x0 = 1.
inline fem::PoissonData<3> mixed_problem() {
  fem::PoissonData<3> data;
  data.source = [](const Point<3>& x, double) { return smooth_u(x); };
  data.dirichlet.push_back(
      {.edges = {0, 2, 3, 4, 5}, .value = [](const Point<3>& x, double) { return smooth_u(x); }});
  data.neumann.push_back({.edges = {kFaceX1}, .value = [](const Point<3>& x, double) {
                            return smooth_grad(x).dot(BentCube::normal_of_face_x1(x));
                          }});
  return data;
}

}  // namespace warpfem::testing3d
