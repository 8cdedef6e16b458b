#include "fem/postprocessing/reference_error.hpp"

#include <Eigen/LU>

#include "core/collective_error.hpp"
#include "core/error.hpp"
#include "fem/assembly/integrate.hpp"
#include "fem/geometry/mesh_point_locator.hpp"

namespace warpfem::fem {

template <int dim>
ErrorNorms error_against_reference(const PoissonProblem<dim>& coarse, const PoissonProblem<dim>& reference) {
  const VectorX uc = coarse.distribution().gather_relevant(coarse.solution());
  const VectorX ur = reference.distribution().gather_all(reference.solution());
  const Mesh<dim>& rmesh = reference.mesh();
  double local[2] = {0, 0};
  // Locating points is rank-local work: a point outside the reference mesh on one
  // rank must end every rank, not leave the others waiting in the sum below.
  run_collectively(coarse.distribution().comm(), [&] {
    const MeshPointLocator<dim> locator(rmesh);
    const LagrangeElement<dim>& ce = coarse.dofs().element();
    const LagrangeElement<dim>& re = reference.dofs().element();
    const LagrangeElement<dim> geo(rmesh.cell_type, 1);
    std::vector<double> ue(static_cast<std::size_t>(ce.num_dofs()));
    Points<dim> xi(1, dim);
    CellValues<dim> values(ce, coarse.geometry(),
                           CellValues<dim>::update_gradients | CellValues<dim>::update_reference_points);
    const auto begin = [&](const CellValues<dim>& v) {
      for (int k = 0; k < ce.num_dofs(); ++k)
        ue[static_cast<std::size_t>(k)] =
            uc(coarse.distribution().relevant_index(coarse.dofs().cell_dofs()(v.cell(), k)));
      return true;
    };
    const auto at_point = [&](const CellValues<dim>& v, Index q) {
      // The reference solution at the same x0: its cell, reference point and
      // Jacobian J_f J_G of that cell.
      const Point<dim> x0 = v.reference_point(q);
      const auto [cell, ref] = locator.locate(x0, "reference solution");
      xi.row(0) = ref.transpose();
      const MatrixX rphi = re.values(xi);
      const auto rdphi = re.gradients(xi);
      const auto dN = geo.gradients(xi);
      Matrix<dim> JG = Matrix<dim>::Zero();
      for (int k = 0; k < geo.num_dofs(); ++k)
        for (int d = 0; d < dim; ++d) JG.col(d) += dN[d](0, k) * rmesh.vertex(rmesh.cells(cell, k));
      double ur_val = 0;
      Point<dim> grad_xi = Point<dim>::Zero();
      for (int k = 0; k < re.num_dofs(); ++k) {
        const double val = ur(reference.dofs().cell_dofs()(cell, k));
        ur_val += val * rphi(0, k);
        for (int d = 0; d < dim; ++d) grad_xi(d) += val * rdphi[static_cast<std::size_t>(d)](0, k);
      }
      const Matrix<dim> J = v.map_jacobian(q) * JG;
      const Point<dim> grad_ref = J.inverse().transpose() * grad_xi;
      const double e = v.value(q, ue.data()) - ur_val;
      local[0] += v.JxW(q) * e * e;
      local[1] += v.JxW(q) * (v.gradient(q, ue.data()) - grad_ref).squaredNorm();
    };
    integrate_cells(coarse.geometry(), values, make_kernel(begin, at_point, [](const CellValues<dim>&) {}));
  });
  double global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, coarse.distribution().comm());
  return {std::sqrt(global[0]), std::sqrt(global[1])};
}

template ErrorNorms error_against_reference(const PoissonProblem<2>&, const PoissonProblem<2>&);
template ErrorNorms error_against_reference(const PoissonProblem<3>&, const PoissonProblem<3>&);

}  // namespace warpfem::fem
