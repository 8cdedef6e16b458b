#include "fem/geometry/simple_cell_geometry.hpp"

#include "core/error.hpp"

namespace warpfem::fem {
namespace {
/// The vertex count as a compile-time constant: the inner loops unroll.
template <int dim, int NV>
void straight_cell_geometry(const Mesh<dim>& mesh, Index cell, Index nq, const MatrixX& N,
                            const std::array<MatrixX, dim>& dN, Points<dim>& x0, Jacobians<dim>& JG,
                            Index offset) {
  double v[dim][NV];  // the cell's vertices, read once
  const TableIndex* c = &mesh.cells(cell, 0);
  for (int k = 0; k < NV; ++k)
    for (int d = 0; d < dim; ++d) v[d][k] = mesh.vertices(c[k], d);
  const Index ldx = x0.rows(), ldj = JG.rows();
  double* X = x0.data() + offset;
  double* G = JG.data() + offset;
  for (Index q = 0; q < nq; ++q) {
    double x[dim] = {}, j[dim][dim] = {};
    for (int k = 0; k < NV; ++k) {
      const double w = N.data()[k * nq + q];  // column-major: (q, k) at k nq + q
      for (int d = 0; d < dim; ++d) {
        x[d] += w * v[d][k];
        for (int e = 0; e < dim; ++e) j[d][e] += v[d][k] * dN[static_cast<std::size_t>(e)].data()[k * nq + q];
      }
    }
    for (int d = 0; d < dim; ++d) {
      X[d * ldx + q] = x[d];
      for (int e = 0; e < dim; ++e) G[(d * dim + e) * ldj + q] = j[d][e];
    }
  }
}
}  // namespace

template <int dim>
void simple_cell_geometry(const Mesh<dim>& mesh, Index cell, Index nq, const MatrixX& N,
                          const std::array<MatrixX, dim>& dN, Points<dim>& x0, Jacobians<dim>& JG,
                          Index offset) {
  switch (vertices_per_cell(mesh.cell_type)) {
    case 3: return straight_cell_geometry<dim, 3>(mesh, cell, nq, N, dN, x0, JG, offset);
    case 4: return straight_cell_geometry<dim, 4>(mesh, cell, nq, N, dN, x0, JG, offset);
    case 8: return straight_cell_geometry<dim, 8>(mesh, cell, nq, N, dN, x0, JG, offset);
    default: throw Error("simple_cell_geometry: unsupported cell type " + to_string(mesh.cell_type));
  }
}

template void simple_cell_geometry<2>(const Mesh<2>&, Index, Index, const MatrixX&,
                                      const std::array<MatrixX, 2>&, Points<2>&, Jacobians<2>&, Index);
template void simple_cell_geometry<3>(const Mesh<3>&, Index, Index, const MatrixX&,
                                      const std::array<MatrixX, 3>&, Points<3>&, Jacobians<3>&, Index);

}  // namespace warpfem::fem
