#include "fem/values/cell_values.hpp"

namespace warpfem::fem {

template <int dim>
CellValues<dim>::CellValues(const LagrangeElement<dim>& element, const WarpedGeometry<dim>& geometry,
                            unsigned update)
    : geometry_(&geometry),
      update_(update),
      nq_(geometry.points_per_cell()),
      n_(element.num_dofs()),
      N_(element.values(geometry.rule().points)),
      dN_(element.gradients(geometry.rule().points)) {
  reference_gradients_.resize(dim, nq_ * n_);
  for (Index q = 0; q < nq_; ++q)
    for (int k = 0; k < n_; ++k)
      for (int d = 0; d < dim; ++d)
        reference_gradients_(d, q * n_ + k) = dN_[static_cast<std::size_t>(d)](q, k);
  grads_.resize(dim, nq_ * n_);
  N_data_ = N_.data();
}

template class CellValues<2>;
template class CellValues<3>;

}  // namespace warpfem::fem
