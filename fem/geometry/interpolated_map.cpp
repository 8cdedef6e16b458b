#include "fem/geometry/interpolated_map.hpp"

#include <Eigen/LU>

#include "core/error.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

template <int dim>
InterpolatedMap<dim>::InterpolatedMap(const Mesh<dim>& mesh, const mapping::Map<dim>& f)
    : mesh_(std::make_shared<const Mesh<dim>>(mesh)), locator_(*mesh_) {
  f.eval(mesh_->vertices, image_);
}

template <int dim>
void InterpolatedMap<dim>::eval_with_jacobian(const Points<dim>& x0, Points<dim>& x,
                                              Jacobians<dim>& J) const {
  const Index n = x0.rows();
  x.resize(n, dim);
  J.resize(n, dim * dim);
  const LagrangeElement<dim> geo(mesh_->cell_type, 1);
  const int nv = geo.num_dofs();
  Points<dim> xi(1, dim);
  for (Index p = 0; p < n; ++p) {
    const auto [cell, ref] = locator_.locate(x0.row(p).transpose(), "interpolated map");
    xi.row(0) = ref.transpose();
    const MatrixX N = geo.values(xi);
    const auto dN = geo.gradients(xi);
    Matrix<dim> dx_dxi = Matrix<dim>::Zero(), dx0_dxi = Matrix<dim>::Zero();
    Point<dim> value = Point<dim>::Zero();
    for (int k = 0; k < nv; ++k) {
      const Index v = mesh_->cells(cell, k);
      const Point<dim> img = image_.row(v).transpose();
      value += N(0, k) * img;
      for (int d = 0; d < dim; ++d) {
        dx_dxi.col(d) += dN[d](0, k) * img;
        dx0_dxi.col(d) += dN[d](0, k) * mesh_->vertex(v);
      }
    }
    x.row(p) = value.transpose();
    set_jacobian_at<dim>(J, p, dx_dxi * dx0_dxi.inverse());
  }
}

template <int dim>
void InterpolatedMap<dim>::eval(const Points<dim>& x0, Points<dim>& x) const {
  Jacobians<dim> J;
  eval_with_jacobian(x0, x, J);
}

template <int dim>
void InterpolatedMap<dim>::jacobian(const Points<dim>& x0, Jacobians<dim>& J) const {
  Points<dim> x;
  eval_with_jacobian(x0, x, J);
}

template <int dim>
std::string InterpolatedMap<dim>::describe() const {
  const bool simplex = mesh_->cell_type == CellType::triangle || mesh_->cell_type == CellType::tetrahedron;
  return "piecewise-" +
         std::string(simplex    ? "linear"
                     : dim == 2 ? "bilinear"
                                : "trilinear") +
         " interpolant of the map on " + std::to_string(mesh_->num_cells()) + " cells";
}

template class InterpolatedMap<2>;
template class InterpolatedMap<3>;

}  // namespace warpfem::fem
