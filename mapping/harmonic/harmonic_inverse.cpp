#include "mapping/harmonic/harmonic_inverse.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/mesh/simplex_neighbours.hpp"
#include "mapping/harmonic/fem_harmonic_map.hpp"
#include "mapping/harmonic/p1_laplace.hpp"

namespace warpfem::mapping {
namespace {

Point<2> row(const Points<2>& P, Index i) {
  return P.row(i).transpose();
}

/// Barycentric coordinates of p in triangle t of mesh (not clamped).
std::array<Real, 3> barycentric(const Mesh<2>& m, Index t, const Point<2>& p) {
  return barycentric_coordinates(m.vertex(m.cells(t, 0)), m.vertex(m.cells(t, 1)), m.vertex(m.cells(t, 2)),
                                 p);
}

}  // namespace

HarmonicInverse::HarmonicInverse(HarmonicMapPtr phi, Real seed_max_edge_length) : phi_(std::move(phi)) {
  if (const auto* fem = dynamic_cast<const FemHarmonicMap*>(phi_.get())) {
    mesh_ = std::shared_ptr<const Mesh<2>>(phi_, &fem->mesh());  // aliasing: lives as long as phi
    images_ = fem->vertex_images();
  } else {
    mesh_ = std::make_shared<const Mesh<2>>(auxiliary_mesh(phi_->domain(), seed_max_edge_length));
    phi_->eval(mesh_->vertices, images_);
  }
  if (!phi_->is_piecewise_linear()) neighbours_ = simplex_neighbours(*mesh_);
  locator_ = std::make_unique<CellLocator>(images_, mesh_->cells, CellType::triangle);
  tol_ = 1e-13 * diameter(phi_->image());
}

HarmonicInverse::Result HarmonicInverse::apply(const Point<2>& z, Point<2>& y, Matrix<2>* J) const {
  const Mesh<2>& m = *mesh_;
  const CellLocator::Nearest hit = locator_->nearest(z);
  Index t = hit.cell;
  const auto T0 = m.cells.row(t);
  y = hit.barycentric[0] * row(m.vertices, T0[0]) + hit.barycentric[1] * row(m.vertices, T0[1]) +
      hit.barycentric[2] * row(m.vertices, T0[2]);
  Result result;
  if (phi_->is_piecewise_linear()) {
    // φ is linear on the triangle: the residual is how far z lies outside it
    // (nonzero only when z is outside the image mesh and the hit was clamped).
    const Point<2> image = hit.barycentric[0] * row(images_, T0[0]) +
                           hit.barycentric[1] * row(images_, T0[1]) +
                           hit.barycentric[2] * row(images_, T0[2]);
    result.residual = (image - z).norm();
    if (J)
      *J = affine_jacobian(row(m.vertices, T0[0]), row(m.vertices, T0[1]), row(m.vertices, T0[2]),
                           row(images_, T0[0]), row(images_, T0[1]), row(images_, T0[2]));
    return result;
  }

  Point<2> phi;
  Matrix<2> Jy;
  phi_->eval_point(y, phi, &Jy);
  Real res = (phi - z).norm();
  for (int it = 0; it < 50 && res > tol_; ++it) {
    ++result.iterations;
    Point<2> step = -(Jy.inverse() * (phi - z));
    if (!step.allFinite()) break;
    bool accepted = false;
    for (int half = 0; half < 12 && !accepted; ++half, step *= 0.5) {
      // clip the step to triangle t; remember the edge it leaves through
      Point<2> s = step;
      Real alpha = 1;
      int exit = -1;
      for (int attempt = 0; attempt < 2; ++attempt) {
        const std::array<Real, 3> b0 = barycentric(m, t, y), b1 = barycentric(m, t, y + s);
        alpha = 1;
        exit = -1;
        for (int i = 0; i < 3; ++i)
          if (b1[i] < 0) {
            const Real a = std::max(b0[i], Real{0}) / (b0[i] - b1[i]);
            if (a < alpha) alpha = a, exit = i;
          }
        if (exit < 0 || neighbours_(t, exit) >= 0) break;
        // leaving Ω: slide along the boundary edge instead
        const auto T = m.cells.row(t);
        const Point<2> e =
            (row(m.vertices, T[(exit + 2) % 3]) - row(m.vertices, T[(exit + 1) % 3])).normalized();
        s = e * e.dot(s);
      }
      const Point<2> candidate = y + alpha * s;
      Point<2> phi_c;
      Matrix<2> J_c;
      phi_->eval_point(candidate, phi_c, &J_c);
      const Real res_c = (phi_c - z).norm();
      if (res_c < res) {
        y = candidate;
        phi = phi_c;
        Jy = J_c;
        res = res_c;
        accepted = true;
        if (exit >= 0 && alpha < 1) {
          const Index nb = neighbours_(t, exit);
          if (nb >= 0) t = nb;
        }
      }
    }
    if (!accepted) break;
  }
  result.residual = res;
  if (J) *J = Jy;
  return result;
}

}  // namespace warpfem::mapping
