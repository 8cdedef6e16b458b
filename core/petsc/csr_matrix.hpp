#pragma once
// A parallel AIJ matrix built on compressed rows we already hold, without
// PETSc copying them entry by entry (MatSeqAIJSetPreallocationCSR inserts row
// by row, which is slow for million-row prolongations). The arrays move into storage
// attached to the matrix and are freed with it.

#include <petscmat.h>

#include <vector>

#include "core/petsc/handles.hpp"

namespace warpfem::petsc {

/// The rows this rank owns of a matrix in compressed form: row r (global row
/// first_row + r) has the columns cols[row_ptr[r] .. row_ptr[r + 1]), global
/// and sorted, with values vals[...]; empty vals stand for zeros (a pattern to
/// be filled later).
struct OwnedRows {
  std::vector<PetscInt> row_ptr, cols;
  std::vector<PetscScalar> vals;
};

/// How PETSc treats an adopted matrix.
struct AdoptOptions {
  /// PETSc's AIJ matrices look for "inodes" (runs of consecutive rows with the
  /// same columns) at every assembly, a pass over all rows; vector problems
  /// have them and get faster products. Scalar problems (one DOF per node:
  /// Poisson, Lagrange prolongations) have none, and PETSc reports "Not using
  /// Inode routines" after the pass, so they say `inodes = false` and skip it.
  /// A user's `-mat_no_inode` option still applies to every matrix.
  bool inodes = true;
};

/// MATSEQAIJ on one rank, MATMPIAIJ (diagonal and off-diagonal blocks split
/// from `rows`) on several. The matrix has rows.row_ptr.size() − 1 local rows,
/// `local_cols` local columns starting at global column `first_col`, and the
/// given global sizes. Collective on `comm`. Throws warpfem::Error on PETSc failure.
Matrix adopt_owned_rows(MPI_Comm comm, OwnedRows rows, PetscInt local_cols, PetscInt first_col,
                        PetscInt global_rows, PetscInt global_cols, const AdoptOptions& options = {});

/// MATMPIAIJ from rows already split into PETSc's two blocks: `diagonal` holds
/// the columns in this rank's column range as local indices (0 .. local_cols),
/// `off_diagonal` the others as global indices; both sorted per row, with the
/// same number of rows; empty vals stand for zeros. Adopted without a copy,
/// like adopt_owned_rows(). Collective on `comm`.
Matrix adopt_split_rows(MPI_Comm comm, OwnedRows diagonal, OwnedRows off_diagonal, PetscInt local_cols,
                        PetscInt global_rows, PetscInt global_cols, const AdoptOptions& options = {});

}  // namespace warpfem::petsc
