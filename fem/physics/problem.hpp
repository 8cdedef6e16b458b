#pragma once
// What every physics gives the rest of the pipeline (multigrid, the run
// recipe, tests): its space, which unknowns are constrained, and its residual
// and Jacobian at a state, assembled over fem/assembly/integrate.hpp and
// petsc::MatrixAssembler. Linear problems also keep an assembled matrix and
// right-hand side.
//
// The space is a Lagrange DOF map with one node distribution and
// `components()` unknowns per node, interleaved node by node: PETSc index
// components() · nodes().global(d) + c (block size components()). Poisson is
// the scalar case, elasticity the vector one (components = dim).

#include <mpi.h>

#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/petsc/handles.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"

namespace warpfem::fem {

/// Where on a load path a state is evaluated: loads scaled by `scale`, data at time `time`.
struct LoadState {
  double scale = 1;
  double time = 0;
};

template <int dim>
class Problem {
 public:
  virtual ~Problem() = default;

  virtual MPI_Comm comm() const = 0;
  virtual const Mesh<dim>& mesh() const = 0;
  /// The scalar DOF map of the nodes (mesh numbering) and its distribution.
  virtual const DofMap& dofs() const = 0;
  virtual const DofDistribution& nodes() const = 0;
  /// Unknowns per node.
  virtual int components() const = 0;
  /// Per component c and mesh DOF d: 1 if unknown (d, c) is constrained, i.e.
  /// its row and column of the Jacobian are the identity's. Every DOF of the
  /// rank's stored mesh, the same on every rank that stores it.
  virtual std::vector<std::vector<char>> constrained() const = 0;

  /// A vector and a matrix of the problem's layout (block size components()).
  virtual petsc::Vector create_vector() const = 0;
  virtual petsc::Matrix create_matrix() const = 0;
  /// R(u) at `load`. Returns false (every rank) if u is outside the problem's
  /// domain (e.g. det F <= 0); r is then unspecified but finite. Collective.
  virtual bool residual(Vec u, const LoadState& load, Vec r) const = 0;
  /// J = ∂R/∂u at u, with identity rows and columns at constrained unknowns. Collective.
  virtual void jacobian(Vec u, const LoadState& load, Mat J) const = 0;
};

/// A problem whose residual is A u − b: A and b are assembled once by assemble().
template <int dim>
class LinearProblem : public Problem<dim> {
 public:
  /// Assembles A and b with the boundary conditions applied.
  virtual void assemble() = 0;
  virtual Mat matrix() const = 0;
  virtual Vec rhs() const = 0;
  /// The unknown, solved for in place.
  virtual Vec solution() const = 0;
};

}  // namespace warpfem::fem
