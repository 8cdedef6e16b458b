#include "core/petsc/scatter.hpp"

#include <algorithm>

#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"

namespace warpfem::petsc {

VectorX scatter_forward(VecScatter scatter, Vec from, Vec to) {
  WARPFEM_PETSC_CHECK(VecScatterBegin(scatter, from, to, INSERT_VALUES, SCATTER_FORWARD));
  WARPFEM_PETSC_CHECK(VecScatterEnd(scatter, from, to, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt n = 0;
  WARPFEM_PETSC_CHECK(VecGetLocalSize(to, &n));
  VectorX out(n);
  const PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(to, &a));
  std::copy(a, a + n, out.data());
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(to, &a));
  return out;
}

std::vector<PetscScalar> gather_to_all(Vec v) {
  Scatter all;
  Vector seq;
  WARPFEM_PETSC_CHECK(VecScatterCreateToAll(v, all.out(), seq.out()));
  const VectorX values = scatter_forward(all.get(), v, seq.get());
  return std::vector<PetscScalar>(values.data(), values.data() + values.size());
}

}  // namespace warpfem::petsc
