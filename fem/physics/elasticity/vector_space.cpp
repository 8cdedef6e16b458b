#include "fem/physics/elasticity/vector_space.hpp"

#include <algorithm>

#include "core/petsc/check.hpp"
#include "core/petsc/scatter.hpp"

namespace warpfem::fem {

template <int dim>
VectorSpace<dim>::VectorSpace(MPI_Comm comm, const Mesh<dim>& mesh, const LagrangeElement<dim>& element,
                              int components, const std::vector<int>& cell_owner)
    : mesh_(mesh),
      components_(components),
      dofs_(mesh, element),
      dist_(cell_owner.empty() ? DofDistribution<dim>(comm, mesh, dofs_)
                               : DofDistribution<dim>(comm, mesh, dofs_, cell_owner)) {}

template <int dim>
petsc::Vector VectorSpace<dim>::create_vector() const {
  petsc::Vector v;
  WARPFEM_PETSC_CHECK(VecCreate(comm(), v.out()));
  WARPFEM_PETSC_CHECK(VecSetSizes(v.get(), num_owned(), num_global()));
  WARPFEM_PETSC_CHECK(VecSetBlockSize(v.get(), components_));
  WARPFEM_PETSC_CHECK(VecSetType(v.get(), VECMPI));
  WARPFEM_PETSC_CHECK(VecSet(v.get(), 0.0));
  return v;
}

template <int dim>
petsc::Matrix VectorSpace<dim>::create_matrix(const char* options_prefix) const {
  std::vector<PetscInt> d_nnz, o_nnz;
  dist_.preallocation(mesh_, dofs_, d_nnz, o_nnz);  // per node row: node columns = block columns
  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(MatCreate(comm(), A.out()));
  WARPFEM_PETSC_CHECK(MatSetSizes(A.get(), num_owned(), num_owned(), num_global(), num_global()));
  WARPFEM_PETSC_CHECK(MatSetBlockSize(A.get(), components_));
  WARPFEM_PETSC_CHECK(MatSetType(A.get(), MATAIJ));
  if (options_prefix) {
    WARPFEM_PETSC_CHECK(MatSetOptionsPrefix(A.get(), options_prefix));
    WARPFEM_PETSC_CHECK(MatSetFromOptions(A.get()));
  }
  WARPFEM_PETSC_CHECK(
      MatXAIJSetPreallocation(A.get(), components_, d_nnz.data(), o_nnz.data(), nullptr, nullptr));
  WARPFEM_PETSC_CHECK(MatSetOption(A.get(), MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  return A;
}

template <int dim>
VectorX VectorSpace<dim>::gather_relevant(Vec v) const {
  const auto& rel = dist_.relevant_dofs();
  const PetscInt n = static_cast<PetscInt>(rel.size()) * components_;
  if (!scatter_) {
    std::vector<PetscInt> blocks(rel.size());
    for (std::size_t i = 0; i < rel.size(); ++i) blocks[i] = dist_.global(rel[i]);
    petsc::IndexSet is;
    WARPFEM_PETSC_CHECK(ISCreateBlock(PETSC_COMM_SELF, components_, static_cast<PetscInt>(blocks.size()),
                                      blocks.data(), PETSC_COPY_VALUES, is.out()));
    WARPFEM_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, n, relevant_values_.out()));
    WARPFEM_PETSC_CHECK(VecScatterCreate(v, is.get(), relevant_values_.get(), nullptr, scatter_.out()));
  }
  return petsc::scatter_forward(scatter_.get(), v, relevant_values_.get());
}

template <int dim>
VectorX VectorSpace<dim>::gather_all(Vec v) const {
  const std::vector<PetscScalar> a = petsc::gather_to_all(v);
  const Index nd = dofs_.num_dofs();
  VectorX out(nd * components_);
  for (Index d = 0; d < nd; ++d)
    for (int c = 0; c < components_; ++c) out(d * components_ + c) = a[global(d, c)];
  return out;
}

template <int dim>
VectorX VectorSpace<dim>::component(const VectorX& interleaved, int c) const {
  const Index n = interleaved.size() / components_;
  VectorX out(n);
  for (Index i = 0; i < n; ++i) out(i) = interleaved(i * components_ + c);
  return out;
}

template class VectorSpace<2>;
template class VectorSpace<3>;

}  // namespace warpfem::fem
