#include "fem/physics/elasticity/near_null_space.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "fem/geometry/warped_geometry.hpp"

namespace warpfem::fem {

template <int dim>
void set_rigid_body_near_null_space(Mat A, const VectorSpace<dim>& space, const mapping::Map<dim>& map) {
  require(space.components() == dim, "rigid-body modes need a displacement space of " + std::to_string(dim) +
                                         " components, got " + std::to_string(space.components()));
  PetscInt rows = 0, cols = 0;
  WARPFEM_PETSC_CHECK(MatGetLocalSize(A, &rows, &cols));
  require(rows == space.num_owned(), "rigid-body modes: the matrix has " + std::to_string(rows) +
                                         " local rows, the space owns " + std::to_string(space.num_owned()));
  // Owned nodes in the order of their global numbers, i.e. of the vector's owned entries.
  const DofDistribution<dim>& dist = space.nodes();
  std::vector<Index> owned;
  for (Index d : dist.relevant_dofs())
    if (dist.owns(d)) owned.push_back(d);
  std::sort(owned.begin(), owned.end(), [&](Index a, Index b) { return dist.global(a) < dist.global(b); });
  Points<dim> x0(static_cast<Index>(owned.size()), dim);
  for (std::size_t i = 0; i < owned.size(); ++i)
    x0.row(static_cast<Index>(i)) = space.dofs().dof_points().row(owned[i]);
  const Points<dim> x = warp_nodes(map, x0);
  petsc::Vector coords = space.create_vector();
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(coords.get(), &a));
  for (std::size_t i = 0; i < owned.size(); ++i)
    for (int c = 0; c < dim; ++c) a[dim * i + static_cast<std::size_t>(c)] = x(static_cast<Index>(i), c);
  WARPFEM_PETSC_CHECK(VecRestoreArray(coords.get(), &a));
  MatNullSpace modes = nullptr;
  WARPFEM_PETSC_CHECK(MatNullSpaceCreateRigidBody(coords.get(), &modes));
  const PetscErrorCode ierr = MatSetNearNullSpace(A, modes);
  WARPFEM_PETSC_CHECK(MatNullSpaceDestroy(&modes));
  WARPFEM_PETSC_CHECK(ierr);
}

template void set_rigid_body_near_null_space<2>(Mat, const VectorSpace<2>&, const mapping::Map<2>&);
template void set_rigid_body_near_null_space<3>(Mat, const VectorSpace<3>&, const mapping::Map<3>&);

}  // namespace warpfem::fem
