#include "fem/geometry/interpolated_map.hpp"

#include <Eigen/LU>

#include "core/error.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

InterpolatedMap::InterpolatedMap(const Mesh<2>& mesh, const mapping::Map<2>& f)
    : mesh_(std::make_shared<const Mesh<2>>(mesh)), locator_(*mesh_) {
  f.eval(mesh_->vertices, image_);
}

void InterpolatedMap::eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const {
  const Index n = x0.rows();
  x.resize(n, 2);
  J.resize(n, 4);
  const LagrangeElement<2> geo(mesh_->cell_type, 1);
  const int nv = geo.num_dofs();
  for (Index p = 0; p < n; ++p) {
    const Point<2> q = x0.row(p).transpose();
    const auto loc = locator_.locate(q);
    if (loc.cell < 0)
      throw Error("interpolated map evaluated outside its mesh at (" + std::to_string(q.x()) + ", " +
                  std::to_string(q.y()) + ")");
    Points<2> xi(1, 2);
    xi.row(0) = loc.xi.transpose();
    const MatrixX N = geo.values(xi);
    const auto dN = geo.gradients(xi);
    Matrix<2> dx_dxi = Matrix<2>::Zero(), dx0_dxi = Matrix<2>::Zero();
    Point<2> value = Point<2>::Zero();
    for (int k = 0; k < nv; ++k) {
      const Index v = mesh_->cells(loc.cell, k);
      const Point<2> img = image_.row(v).transpose();
      value += N(0, k) * img;
      for (int d = 0; d < 2; ++d) {
        dx_dxi.col(d) += dN[d](0, k) * img;
        dx0_dxi.col(d) += dN[d](0, k) * mesh_->vertex(v);
      }
    }
    x.row(p) = value.transpose();
    set_jacobian_at<2>(J, p, dx_dxi * dx0_dxi.inverse());
  }
}

void InterpolatedMap::eval(const Points<2>& x0, Points<2>& x) const {
  Jacobians<2> J;
  eval_with_jacobian(x0, x, J);
}

void InterpolatedMap::jacobian(const Points<2>& x0, Jacobians<2>& J) const {
  Points<2> x;
  eval_with_jacobian(x0, x, J);
}

std::string InterpolatedMap::describe() const {
  return "piecewise-" + std::string(mesh_->cell_type == CellType::triangle ? "linear" : "bilinear") +
         " interpolant of the map on " + std::to_string(mesh_->num_cells()) + " cells";
}

}  // namespace warpfem::fem
