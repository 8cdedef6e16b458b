#pragma once
// A vector-valued Lagrange space: `components` (by default dim) copies of a
// scalar P1/P2/Q1/Q2 space sharing one fem::DofMap (mesh numbering of the nodes) and one
// fem::DofDistribution (cell partition and node ownership). PETSc vectors and
// matrices have block size `components`, interleaved by node:
//   PETSc global index of component c of node d = components * dist.global(d) + c.
//
// Not copyable or movable: the distribution keeps a pointer to the DOF map.

#include <mpi.h>

#include <vector>

#include "core/petsc/handles.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"

namespace warpfem::fem {

template <int dim>
class VectorSpace {
 public:
  /// `cell_owner`: the rank of every cell (empty: partition_cells()), e.g. the
  /// finest entry of fem::nested_partitions() for a multigrid hierarchy.
  VectorSpace(MPI_Comm comm, const Mesh<dim>& mesh, const LagrangeElement<dim>& element, int components = dim,
              const std::vector<int>& cell_owner = {});
  VectorSpace(const VectorSpace&) = delete;
  VectorSpace& operator=(const VectorSpace&) = delete;

  MPI_Comm comm() const { return dist_.comm(); }
  int components() const { return components_; }
  const Mesh<dim>& mesh() const { return mesh_; }
  const DofMap<dim>& dofs() const { return dofs_; }
  /// The scalar (node) distribution.
  const DofDistribution<dim>& nodes() const { return dist_; }
  PetscInt num_owned() const { return components_ * dist_.num_owned(); }
  PetscInt num_global() const { return components_ * dist_.num_global(); }
  PetscInt global(Index node, int component) const { return components_ * dist_.global(node) + component; }

  /// A parallel vector of this layout (block size `components`).
  petsc::Vector create_vector() const;
  /// A MATAIJ matrix (block size `components`, type changeable with -<prefix>mat_type baij)
  /// preallocated from the scalar coupling pattern; inserting outside it is an error.
  petsc::Matrix create_matrix(const char* options_prefix = nullptr) const;

  /// Values of `v` at relevant_dofs() x components, interleaved (node-major), via a cached scatter.
  VectorX gather_relevant(Vec v) const;
  /// Values of every node (mesh order) x components on every rank (tests, small outputs).
  VectorX gather_all(Vec v) const;
  /// Component `c` of an interleaved relevant vector (as fem::OutputMesh<dim>::interpolate expects).
  VectorX component(const VectorX& interleaved, int c) const;

 private:
  const Mesh<dim>& mesh_;
  int components_;
  DofMap<dim> dofs_;
  DofDistribution<dim> dist_;
  mutable petsc::Scatter scatter_;
  mutable petsc::Vector relevant_values_;
};

}  // namespace warpfem::fem
