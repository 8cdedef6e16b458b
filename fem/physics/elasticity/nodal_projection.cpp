#include "fem/physics/elasticity/nodal_projection.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "fem/assembly/integrate.hpp"

namespace warpfem::fem {

template <int dim>
NodalProjection<dim>::NodalProjection(MPI_Comm comm, const Mesh<dim>& mesh,
                                      const WarpedGeometry<dim>& geometry, const std::vector<int>& cell_owner)
    : geometry_(geometry),
      dofs_(mesh, LagrangeElement<dim>(mesh.cell_type, 1)),
      dist_(cell_owner.empty() ? DofDistribution<dim>(comm, mesh, dofs_)
                               : DofDistribution<dim>(comm, mesh, dofs_, cell_owner)) {
  require(std::equal(dist_.local_cells().begin(), dist_.local_cells().end(), geometry_.cells().begin(),
                     geometry_.cells().end()),
          "NodalProjection: the geometry's cells are not this rank's cells of the partition");
  weights_ = dist_.create_vector();
  accumulate(weights_.get(), [](Index, Index) { return 1.0; });
}

template <int dim>
template <class Value>
void NodalProjection<dim>::accumulate(Vec sum, Value&& value) const {
  WARPFEM_PETSC_CHECK(VecSet(sum, 0.0));
  const int n = dofs_.element().num_dofs();
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ve(n);
  CellValues<dim> values(dofs_.element(), geometry_, 0);
  integrate_cells(geometry_, values,
                  make_kernel(
                      [&](const CellValues<dim>&) {
                        ve.setZero();
                        return true;
                      },
                      [&](const CellValues<dim>& v, Index q) {
                        const double w = v.JxW(q) * value(v.position(), q);
                        for (int k = 0; k < n; ++k) ve(k) += w * v.shape_value(q, k);
                      },
                      [&](const CellValues<dim>& v) {
                        for (int k = 0; k < n; ++k) idx[k] = dist_.global(dofs_.cell_dofs()(v.cell(), k));
                        WARPFEM_PETSC_CHECK(
                            VecSetValues(sum, static_cast<PetscInt>(n), idx.data(), ve.data(), ADD_VALUES));
                      }));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(sum));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(sum));
}

template <int dim>
VectorX NodalProjection<dim>::project(const std::vector<std::vector<double>>& values) const {
  petsc::Vector sum = dist_.create_vector();
  accumulate(sum.get(), [&](Index i, Index q) {
    return values[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)];
  });
  WARPFEM_PETSC_CHECK(VecPointwiseDivide(sum.get(), sum.get(), weights_.get()));
  return dist_.gather_relevant(sum.get());
}

template class NodalProjection<2>;
template class NodalProjection<3>;

}  // namespace warpfem::fem
