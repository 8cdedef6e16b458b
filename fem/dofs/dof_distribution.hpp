#pragma once
// Parallel ownership and PETSc numbering of the DOFs of a DofMap (2D or 3D).
//
// Cells are owned by the rank partition_cells() (or the caller) gives them; a DOF is owned by
// the owner of the first cell (in cell order) that contains it. PETSc global indices number
// the DOFs of rank 0 first, then rank 1, ..., so every rank owns one contiguous
// range [owned_begin, owned_end). Within a rank: P1/Q1 in vertex order (which
// refine_uniformly makes the order of first use by the cells), higher orders
// in order of first use by the cells, so a cell's DOFs end up close together
// (vertex and edge nodes interleaved, which keeps matrix-vector products cache
// friendly).

#include <mpi.h>
#include <petscvec.h>

#include <array>
#include <memory>
#include <mutex>
#include <vector>

#include "core/petsc/handles.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/hierarchy/nested_blocks.hpp"

namespace warpfem::fem {

template <int dim>
class DofDistribution {
 public:
  /// Cells partitioned by partition_cells().
  DofDistribution(MPI_Comm comm, const Mesh<dim>& mesh, const DofMap<dim>& dofs);
  /// Cells partitioned by `cell_owner` (one rank in [0, size) per cell, the same
  /// on every rank), e.g. a nested partition of a hierarchy (nested_partitions()).
  DofDistribution(MPI_Comm comm, const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                  const std::vector<int>& cell_owner);
  /// Cells partitioned by `blocks` (a level above the base of
  /// nested_level_partitions(), or of a MeshHierarchy built for a partition).
  /// The same distribution as with every cell's owner listed, but P1/Q1 owners
  /// and numbers follow from the blocks' vertex ranges (no pass over the cells:
  /// the mesh may be partial), and on several ranks the sparsity pattern visits
  /// only the cells of the blocks near the rank's.
  DofDistribution(MPI_Comm comm, const Mesh<dim>& mesh, const DofMap<dim>& dofs, const NestedBlocks& blocks);

  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }
  /// Cells this rank assembles.
  const std::vector<Index>& local_cells() const { return local_cells_; }
  PetscInt owned_begin() const { return owned_begin_; }
  PetscInt owned_end() const { return owned_end_; }
  PetscInt num_owned() const { return owned_end_ - owned_begin_; }
  PetscInt num_global() const { return num_global_; }
  /// PETSc global index of a mesh DOF.
  PetscInt global(Index dof) const { return global_[static_cast<std::size_t>(dof)]; }
  bool owns(Index dof) const { return owner_[static_cast<std::size_t>(dof)] == rank_; }
  int owner(Index dof) const { return owner_[static_cast<std::size_t>(dof)]; }
  /// Mesh DOFs touched by the local cells (owned and ghost), sorted. Built on
  /// first use (thread-safe): multigrid levels never ask for it.
  const std::vector<Index>& relevant_dofs() const {
    std::call_once(*relevant_once_, [this] { build_relevant(); });
    return relevant_;
  }
  /// Position of a mesh DOF in relevant_dofs(), or -1.
  Index relevant_index(Index dof) const {
    std::call_once(*relevant_once_, [this] { build_relevant(); });
    return relevant_index_[static_cast<std::size_t>(dof)];
  }

  /// A new parallel vector with this layout.
  petsc::Vector create_vector() const;
  /// Values of `v` at relevant_dofs() (owned and ghost), via a cached PETSc scatter.
  VectorX gather_relevant(Vec v) const;
  /// Values of `v` at every mesh DOF on every rank (for tests and small outputs).
  VectorX gather_all(Vec v) const;
  /// Per-row counts of nonzeros in the diagonal and off-diagonal blocks for
  /// the owned rows of a matrix coupling all DOFs of each cell.
  void preallocation(const Mesh<dim>& mesh, const DofMap<dim>& dofs, std::vector<PetscInt>& d_nnz,
                     std::vector<PetscInt>& o_nnz) const;
  /// The same pattern as compressed rows: owned row r (global index owned_begin() + r)
  /// couples to the sorted global columns cols[row_ptr[r] .. row_ptr[r + 1]).
  void sparsity(const Mesh<dim>& mesh, const DofMap<dim>& dofs, std::vector<PetscInt>& row_ptr,
                std::vector<PetscInt>& cols) const;
  /// The same pattern split the way PETSc's MATMPIAIJ stores it (for
  /// petsc::adopt_split_rows): the columns in [owned_begin(), owned_end()) as
  /// local indices in (row_ptr, cols), the others as global indices in
  /// (off_row_ptr, off_cols). Saves adopting the unsplit rows a second pass.
  void sparsity_split(const Mesh<dim>& mesh, const DofMap<dim>& dofs, std::vector<PetscInt>& row_ptr,
                      std::vector<PetscInt>& cols, std::vector<PetscInt>& off_row_ptr,
                      std::vector<PetscInt>& off_cols) const;

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  std::vector<Index> local_cells_;
  std::vector<int> owner_;
  std::vector<PetscInt> global_;
  PetscInt owned_begin_ = 0, owned_end_ = 0, num_global_ = 0;
  /// Cell ranges [first, last) that can contain an owned DOF (empty: all cells).
  std::vector<std::array<Index, 2>> candidate_cells_;
  void check_owners(Index num_cells, Index num_listed, int lowest, int highest) const;
  /// sparsity() and sparsity_split(): off_row_ptr / off_cols null for the unsplit pattern.
  void pattern(const Mesh<dim>& mesh, const DofMap<dim>& dofs, std::vector<PetscInt>& row_ptr,
               std::vector<PetscInt>& cols, std::vector<PetscInt>* off_row_ptr,
               std::vector<PetscInt>* off_cols) const;
  /// pattern() in 3D: from the cells of each row rather than a buffer of
  /// candidate columns (3D rows take many more: cells per DOF × DOFs per cell).
  void pattern_by_row_cells(const DofMap<dim>& dofs, const std::vector<std::array<Index, 2>>& scanned,
                            std::vector<PetscInt>& row_ptr, std::vector<PetscInt>& cols,
                            std::vector<PetscInt>* off_row_ptr, std::vector<PetscInt>* off_cols) const;
  /// Owners of the DOFs by a pass over the cells (the first cell containing a DOF decides).
  template <class CellOwner>
  void own_by_cells(const Mesh<dim>& mesh, const DofMap<dim>& dofs, const CellOwner& cell_owner);
  /// PETSc numbers from owner_: rank by rank (see the class comment).
  void number(const Mesh<dim>& mesh, const DofMap<dim>& dofs);
  void build_relevant() const;
  // relevant_dofs() and its inverse, built once on demand (the flag on the heap
  // keeps the class movable).
  mutable std::unique_ptr<std::once_flag> relevant_once_ = std::make_unique<std::once_flag>();
  mutable std::vector<Index> relevant_;
  mutable std::vector<Index> relevant_index_;
  mutable petsc::Scatter scatter_;
  mutable petsc::Vector relevant_values_;
  const DofMap<dim>* dofs_;
};

}  // namespace warpfem::fem
