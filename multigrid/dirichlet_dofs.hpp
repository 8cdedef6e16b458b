#pragma once
// Which DOFs of a level carry a Dirichlet condition: the DOFs whose rows and
// columns fem::PoissonProblem eliminates, selected the same way (per DOF node
// through the boundary polygon if PoissonData has one, else by facet tag).

#include <vector>

#include "fem/dofs/dof_map.hpp"
#include "fem/physics/poisson.hpp"

namespace warpfem::multigrid {

/// Per mesh DOF of `dofs`: 1 if a Dirichlet condition of `data` applies at it, else 0.
std::vector<char> dirichlet_dofs(const warpfem::Mesh<2>& mesh, const fem::DofMap<2>& dofs,
                                 const fem::PoissonData& data);

}  // namespace warpfem::multigrid
