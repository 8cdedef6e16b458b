#pragma once
// The cube [-1,1]³ onto the closed unit ball, for the benchmark against
// deal.II's ball (benchmark only, not a library map):
//
//   f(x, y, z) = (x √(1 − y²/2 − z²/2 + y²z²/3),
//                 y √(1 − z²/2 − x²/2 + z²x²/3),
//                 z √(1 − x²/2 − y²/2 + x²y²/3)),
//
// the volume form of Nowell's cube-to-sphere map. Every radicand is ≥ 1/3 on
// the closed cube, so f is analytic there. On a face, e.g. x = 1, |f|² = 1
// identically, and f maps the cube's surface homeomorphically onto the sphere.
// Why f is a bijection onto the ball: det J_f > 0 in the open cube (checked on
// probes by check_cube_to_ball, down to 1e-6 from faces, edges and corners),
// so by degree theory every point of the open ball has exactly one preimage
// (the boundary map has degree 1 and each preimage counts +1) and no point
// outside has any. det J_f vanishes on the cube's edges and corners — no C¹
// map of the closed cube onto the ball can avoid that, since an invertible
// J_f would map the 90° wedge at an edge to a wedge under 180°, while the
// sphere is smooth — so cells along the edges are flattened; the quadrature
// points are interior, where det J_f > 0.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mapping/map.hpp"

namespace warpfem::bench {

class CubeToBallMap final : public mapping::Map<3> {
 public:
  void eval(const Points<3>& x0, Points<3>& x) const override {
    x.resize(x0.rows(), 3);
    for (Index p = 0; p < x0.rows(); ++p) {
      const Terms t(x0(p, 0), x0(p, 1), x0(p, 2));
      x(p, 0) = t.x * t.sx, x(p, 1) = t.y * t.sy, x(p, 2) = t.z * t.sz;
    }
  }
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override {
    J.resize(x0.rows(), 9);
    for (Index p = 0; p < x0.rows(); ++p) Terms(x0(p, 0), x0(p, 1), x0(p, 2)).jacobian(J, p);
  }
  void eval_with_jacobian(const Points<3>& x0, Points<3>& x, Jacobians<3>& J) const override {
    x.resize(x0.rows(), 3);
    J.resize(x0.rows(), 9);
    for (Index p = 0; p < x0.rows(); ++p) {
      const Terms t(x0(p, 0), x0(p, 1), x0(p, 2));
      x(p, 0) = t.x * t.sx, x(p, 1) = t.y * t.sy, x(p, 2) = t.z * t.sz;
      t.jacobian(J, p);
    }
  }
  std::string describe() const override { return "cube [-1,1]^3 onto the unit ball (Nowell)"; }

 private:
  struct Terms {
    double x, y, z, a, b, c, sx, sy, sz;
    Terms(double x_, double y_, double z_)
        : x(x_),
          y(y_),
          z(z_),
          a(x_ * x_),
          b(y_ * y_),
          c(z_ * z_),
          sx(std::sqrt(1 - b / 2 - c / 2 + b * c / 3)),
          sy(std::sqrt(1 - c / 2 - a / 2 + c * a / 3)),
          sz(std::sqrt(1 - a / 2 - b / 2 + a * b / 3)) {}
    /// Row-major J_f into row p of J.
    void jacobian(Jacobians<3>& J, Index p) const {
      J(p, 0) = sx;
      J(p, 1) = -x * y * (1 - 2 * c / 3) / (2 * sx);
      J(p, 2) = -x * z * (1 - 2 * b / 3) / (2 * sx);
      J(p, 3) = -y * x * (1 - 2 * c / 3) / (2 * sy);
      J(p, 4) = sy;
      J(p, 5) = -y * z * (1 - 2 * a / 3) / (2 * sy);
      J(p, 6) = -z * x * (1 - 2 * b / 3) / (2 * sz);
      J(p, 7) = -z * y * (1 - 2 * a / 3) / (2 * sz);
      J(p, 8) = sz;
    }
  };
};

/// What check_cube_to_ball found; ok if every probe passed.
struct CubeToBallCheck {
  double min_det_interior = std::numeric_limits<double>::max();  ///< grid points at least 0.05 inside
  double min_det_near_boundary =
      std::numeric_limits<double>::max();  ///< probes 1e-6..1e-1 from faces/edges/corners
  double max_jacobian_error = 0;           ///< against central differences, relative to |J|
  double max_sphere_error = 0;             ///< | |f| − 1 | on the faces
  bool ok = false;
};

/// det J_f > 0 on a grid of the cube and on probes approaching every kind of
/// boundary point, J_f against central differences, |f| = 1 on the faces.
inline CubeToBallCheck check_cube_to_ball(const CubeToBallMap& f) {
  CubeToBallCheck out;
  const auto det = [](const Jacobians<3>& J, Index p) {
    return J(p, 0) * (J(p, 4) * J(p, 8) - J(p, 5) * J(p, 7)) -
           J(p, 1) * (J(p, 3) * J(p, 8) - J(p, 5) * J(p, 6)) +
           J(p, 2) * (J(p, 3) * J(p, 7) - J(p, 4) * J(p, 6));
  };
  const int n = 40;
  Points<3> grid((n + 1) * (n + 1) * (n + 1), 3);
  Index k = 0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int l = 0; l <= n; ++l)
        grid.row(k++) = Point<3>(-0.95 + 1.9 * i / n, -0.95 + 1.9 * j / n, -0.95 + 1.9 * l / n);
  Points<3> x;
  Jacobians<3> J;
  f.eval_with_jacobian(grid, x, J);
  for (Index p = 0; p < grid.rows(); ++p) out.min_det_interior = std::min(out.min_det_interior, det(J, p));
  // Toward a corner, the middle of an edge, the middle of a face, and points
  // of faces and edges off their middles, from 1e-1 down to 1e-6.
  const Point<3> targets[] = {{1, 1, 1}, {-1, 1, -1},   {1, 1, 0},      {1, 0.3, -1},  {0, -1, 1},
                              {1, 0, 0}, {1, 0.7, 0.2}, {0.4, -1, 0.9}, {1, 1, 0.999}, {0.999, 0.999, 0.999}};
  std::vector<Point<3>> probes;
  for (const Point<3>& t : targets)
    for (double d = 1e-1; d >= 1e-6; d /= 10) probes.push_back(t * (1 - d));
  Points<3> near(static_cast<Index>(probes.size()), 3);
  for (std::size_t p = 0; p < probes.size(); ++p) near.row(static_cast<Index>(p)) = probes[p];
  f.eval_with_jacobian(near, x, J);
  for (Index p = 0; p < near.rows(); ++p)
    out.min_det_near_boundary = std::min(out.min_det_near_boundary, det(J, p));
  // Central differences at the grid's points (a sample of them).
  const double h = 1e-6;
  for (Index p = 0; p < grid.rows(); p += 37) {
    Points<3> q = grid.row(p);
    Jacobians<3> Jp;
    f.jacobian(q, Jp);
    for (int c = 0; c < 3; ++c) {
      Points<3> qp = q, qm = q, xp, xm;
      qp(0, c) += h, qm(0, c) -= h;
      f.eval(qp, xp);
      f.eval(qm, xm);
      for (int r = 0; r < 3; ++r)
        out.max_jacobian_error =
            std::max(out.max_jacobian_error,
                     std::abs((xp(0, r) - xm(0, r)) / (2 * h) - Jp(0, 3 * r + c)) / Jp.row(0).norm());
    }
  }
  // The faces onto the sphere.
  Points<3> face(6 * (n + 1) * (n + 1), 3);
  k = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double side : {-1.0, 1.0})
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Point<3> q;
          q[axis] = side, q[(axis + 1) % 3] = -1 + 2.0 * i / n, q[(axis + 2) % 3] = -1 + 2.0 * j / n;
          face.row(k++) = q;
        }
  f.eval(face, x);
  for (Index p = 0; p < face.rows(); ++p)
    out.max_sphere_error = std::max(out.max_sphere_error, std::abs(x.row(p).norm() - 1));
  out.ok = out.min_det_interior > 0 && out.min_det_near_boundary > 0 && out.max_jacobian_error < 1e-6 &&
           out.max_sphere_error < 1e-14;
  return out;
}

}  // namespace warpfem::bench
