#include "fem/reference_error.hpp"

#include <Eigen/LU>

#include "core/error.hpp"
#include "fem/cell_locator.hpp"

namespace warpfem::fem {

ErrorNorms error_against_reference(const PoissonProblem& coarse, const PoissonProblem& reference) {
  const VectorX uc = coarse.distribution().gather_relevant(coarse.solution());
  const VectorX ur = reference.distribution().gather_all(reference.solution());
  const Mesh<2>& rmesh = reference.mesh();
  const CellLocator locator(rmesh);
  const LagrangeElement<2>& ce = coarse.dofs().element();
  const LagrangeElement<2>& re = reference.dofs().element();
  const LagrangeElement<2> geo(rmesh.cell_type, 1);
  const WarpedGeometry& g = coarse.geometry();
  const MatrixX phi = ce.values(g.rule().points);
  const auto dphi = ce.gradients(g.rule().points);
  double local[2] = {0, 0};
  Points<2> xi(1, 2), x0c;
  Jacobians<2> JGc;
  g.for_each_chunk([&](const GeometryChunk& chunk) {
    for (Index i = 0; i < chunk.num_cells(); ++i) {
      const Index cell = chunk.first_cell() + i;
      const Index c = g.cells()[static_cast<std::size_t>(cell)];
      g.cell_reference_geometry(cell, x0c, JGc);
      for (Index q = 0; q < g.points_per_cell(); ++q) {
        const Index p = chunk.at(i, q);
        double uh = 0, gu = 0, gv = 0;
        for (int k = 0; k < ce.num_dofs(); ++k) {
          const double val = uc(coarse.distribution().relevant_index(coarse.dofs().cell_dofs()(c, k)));
          uh += val * phi(q, k);
          gu += val * dphi[0](q, k);
          gv += val * dphi[1](q, k);
        }
        Matrix<2> JinvT;
        JinvT << chunk.inverse_transpose(p, 0), chunk.inverse_transpose(p, 1), chunk.inverse_transpose(p, 2),
            chunk.inverse_transpose(p, 3);
        const Point<2> grad_h = JinvT * Point<2>(gu, gv);

        const Point<2> x0 = x0c.row(q).transpose();
        const auto loc = locator.locate(x0);
        if (loc.cell < 0) throw Error("reference solution: quadrature point outside the reference mesh");
        xi.row(0) = loc.xi.transpose();
        const MatrixX rphi = re.values(xi);
        const auto rdphi = re.gradients(xi);
        const MatrixX N = geo.values(xi);
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
        // J_f = J_c J_Gc⁻¹ with J_c = (J_c^{-T})^{-T} the coarse Jacobian.
        const Matrix<2> Jc = JinvT.transpose().inverse();
        const Matrix<2> J = Jc * jacobian_at<2>(JGc, q).inverse() * JG;
        const Point<2> grad_ref = J.inverse().transpose() * grad_xi;
        const double w = chunk.JxW(p);
        local[0] += w * (uh - ur_val) * (uh - ur_val);
        local[1] += w * (grad_h - grad_ref).squaredNorm();
      }
    }
  });
  double global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, coarse.distribution().comm());
  return {std::sqrt(global[0]), std::sqrt(global[1])};
}

}  // namespace warpfem::fem
