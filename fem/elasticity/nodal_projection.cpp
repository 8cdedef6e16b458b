#include "fem/elasticity/nodal_projection.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::fem {

NodalProjection::NodalProjection(MPI_Comm comm, const Mesh<2>& mesh, const WarpedGeometry& geometry,
                                 const std::vector<int>& cell_owner)
    : geometry_(geometry),
      dofs_(mesh, LagrangeElement<2>(mesh.cell_type, 1)),
      dist_(cell_owner.empty() ? DofDistribution(comm, mesh, dofs_)
                               : DofDistribution(comm, mesh, dofs_, cell_owner)) {
  require(std::equal(dist_.local_cells().begin(), dist_.local_cells().end(), geometry_.cells().begin(),
                     geometry_.cells().end()),
          "NodalProjection: the geometry's cells are not this rank's cells of the partition");
  phi_ = dofs_.element().values(geometry_.rule().points);
  weights_ = dist_.create_vector();
  WARPFEM_PETSC_CHECK(VecSet(weights_.get(), 0.0));
  const Index n = phi_.cols();
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX we(n);
  for (Index i = 0; i < geometry_.num_cells(); ++i) {
    we.setZero();
    for (Index q = 0; q < geometry_.points_per_cell(); ++q)
      we += geometry_.JxW()(geometry_.at(i, q)) * phi_.row(q).transpose();
    for (Index k = 0; k < n; ++k) idx[k] = dist_.global(dofs_.cell_dofs()(geometry_.cells()[i], k));
    WARPFEM_PETSC_CHECK(
        VecSetValues(weights_.get(), static_cast<PetscInt>(n), idx.data(), we.data(), ADD_VALUES));
  }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(weights_.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(weights_.get()));
}

VectorX NodalProjection::project(const std::vector<std::vector<double>>& values) const {
  petsc::Vector sum = dist_.create_vector();
  WARPFEM_PETSC_CHECK(VecSet(sum.get(), 0.0));
  const Index n = phi_.cols();
  std::vector<PetscInt> idx(static_cast<std::size_t>(n));
  VectorX ve(n);
  for (Index i = 0; i < geometry_.num_cells(); ++i) {
    ve.setZero();
    for (Index q = 0; q < geometry_.points_per_cell(); ++q)
      ve += (geometry_.JxW()(geometry_.at(i, q)) *
             values[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)]) *
            phi_.row(q).transpose();
    for (Index k = 0; k < n; ++k) idx[k] = dist_.global(dofs_.cell_dofs()(geometry_.cells()[i], k));
    WARPFEM_PETSC_CHECK(VecSetValues(sum.get(), static_cast<PetscInt>(n), idx.data(), ve.data(), ADD_VALUES));
  }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(sum.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(sum.get()));
  WARPFEM_PETSC_CHECK(VecPointwiseDivide(sum.get(), sum.get(), weights_.get()));
  return dist_.gather_relevant(sum.get());
}

}  // namespace warpfem::fem
