#include "fem/postprocessing/reference_error.hpp"

#include <Eigen/LU>

#include "core/error.hpp"
#include "core/mesh/cell_locator.hpp"
#include "fem/assembly/integrate.hpp"

namespace warpfem::fem {

ErrorNorms error_against_reference(const PoissonProblem<2>& coarse, const PoissonProblem<2>& reference) {
  const VectorX uc = coarse.distribution().gather_relevant(coarse.solution());
  const VectorX ur = reference.distribution().gather_all(reference.solution());
  const Mesh<2>& rmesh = reference.mesh();
  const CellLocator locator(rmesh);
  const LagrangeElement<2>& ce = coarse.dofs().element();
  const LagrangeElement<2>& re = reference.dofs().element();
  const LagrangeElement<2> geo(rmesh.cell_type, 1);
  std::vector<double> ue(static_cast<std::size_t>(ce.num_dofs()));
  double local[2] = {0, 0};
  Points<2> xi(1, 2);
  CellValues<2> values(ce, coarse.geometry(),
                       CellValues<2>::update_gradients | CellValues<2>::update_reference_points);
  const auto begin = [&](const CellValues<2>& v) {
    for (int k = 0; k < ce.num_dofs(); ++k)
      ue[static_cast<std::size_t>(k)] =
          uc(coarse.distribution().relevant_index(coarse.dofs().cell_dofs()(v.cell(), k)));
    return true;
  };
  const auto at_point = [&](const CellValues<2>& v, Index q) {
    // The reference solution at the same x0: its cell, reference point and
    // Jacobian J_f J_G of that cell.
    const Point<2> x0 = v.reference_point(q);
    const auto loc = locator.locate(x0);
    if (loc.cell < 0) throw Error("reference solution: quadrature point outside the reference mesh");
    xi.row(0) = loc.xi.transpose();
    const MatrixX rphi = re.values(xi);
    const auto rdphi = re.gradients(xi);
    const auto dN = geo.gradients(xi);
    Matrix<2> JG = Matrix<2>::Zero();
    for (int k = 0; k < geo.num_dofs(); ++k)
      for (int d = 0; d < 2; ++d) JG.col(d) += dN[d](0, k) * rmesh.vertex(rmesh.cells(loc.cell, k));
    double ur_val = 0;
    Point<2> grad_xi = Point<2>::Zero();
    for (int k = 0; k < re.num_dofs(); ++k) {
      const double val = ur(reference.dofs().cell_dofs()(loc.cell, k));
      ur_val += val * rphi(0, k);
      grad_xi += val * Point<2>(rdphi[0](0, k), rdphi[1](0, k));
    }
    const Matrix<2> J = v.map_jacobian(q) * JG;
    const Point<2> grad_ref = J.inverse().transpose() * grad_xi;
    const double e = v.value(q, ue.data()) - ur_val;
    local[0] += v.JxW(q) * e * e;
    local[1] += v.JxW(q) * (v.gradient(q, ue.data()) - grad_ref).squaredNorm();
  };
  integrate_cells(coarse.geometry(), values, make_kernel(begin, at_point, [](const CellValues<2>&) {}));
  double global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, coarse.distribution().comm());
  return {std::sqrt(global[0]), std::sqrt(global[1])};
}

}  // namespace warpfem::fem
