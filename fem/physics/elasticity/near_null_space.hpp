#pragma once
// The rigid-body near-null space of a vector space for algebraic multigrid
// (-pc_type gamg reads it through MatGetNearNullSpace) and for checks of a
// stiffness matrix: dim translations and dim(dim − 1)/2 rotations.
//
// The rotations turn about the *warped* node positions f(x0): the PDE lives on
// f(Ω0), so a rotation of the parametrization coordinates x0 is rigid in the
// physical domain only if f is a similarity. Where f is affine the modes are
// exactly in the kernel of the small-strain stiffness; for a curved f they are
// there up to the interpolation error of f in the element space.

#include <petscmat.h>

#include "fem/physics/elasticity/vector_space.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

/// Attaches the rigid-body modes of `space` (components = dim, nodes placed by
/// `map`) to `A` with MatSetNearNullSpace. Evaluates the map once at the owned
/// nodes. Collective. Throws warpfem::Error if the space is not a displacement
/// space (components ≠ dim) or A's local row count differs from the space's.
template <int dim>
void set_rigid_body_near_null_space(Mat A, const VectorSpace<dim>& space, const mapping::Map<dim>& map);

}  // namespace warpfem::fem
