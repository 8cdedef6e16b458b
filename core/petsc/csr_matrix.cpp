#include "core/petsc/csr_matrix.hpp"

#include <memory>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::petsc {
namespace {

/// Compressed arrays kept alive by the matrix that uses them.
struct Storage {
  OwnedRows diagonal, off_diagonal;  // off_diagonal stays empty on one rank
};

PetscErrorCode destroy_storage(void* p) {
  delete static_cast<Storage*>(p);
  return 0;
}

/// Hands `storage` to `A`: PETSc destroys it with the matrix.
void attach(Mat A, std::unique_ptr<Storage> storage) {
  PetscContainer container = nullptr;
  WARPFEM_PETSC_CHECK(PetscContainerCreate(PetscObjectComm(reinterpret_cast<PetscObject>(A)), &container));
  WARPFEM_PETSC_CHECK(PetscContainerSetPointer(container, storage.get()));
  WARPFEM_PETSC_CHECK(PetscContainerSetUserDestroy(container, destroy_storage));
  storage.release();  // owned by the container from here on
  WARPFEM_PETSC_CHECK(PetscObjectCompose(reinterpret_cast<PetscObject>(A), "warpfem_csr_storage",
                                         reinterpret_cast<PetscObject>(container)));
  WARPFEM_PETSC_CHECK(PetscContainerDestroy(&container));  // the matrix keeps its reference
}

}  // namespace

Matrix adopt_owned_rows(MPI_Comm comm, OwnedRows rows, PetscInt local_cols, PetscInt first_col,
                        PetscInt global_rows, PetscInt global_cols) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const PetscInt local_rows = static_cast<PetscInt>(rows.row_ptr.size()) - 1;
  auto storage = std::make_unique<Storage>();
  Matrix A;
  if (rows.vals.empty()) rows.vals.assign(size == 1 ? rows.cols.size() : 0, 0.0);
  require(rows.vals.empty() || rows.vals.size() == rows.cols.size(),
          "adopt_owned_rows: " + std::to_string(rows.vals.size()) + " values for " +
              std::to_string(rows.cols.size()) + " columns");
  if (size == 1) {
    storage->diagonal = std::move(rows);
    OwnedRows& d = storage->diagonal;
    WARPFEM_PETSC_CHECK(MatCreateSeqAIJWithArrays(comm, local_rows, local_cols, d.row_ptr.data(),
                                                  d.cols.data(), d.vals.data(), A.out()));
  } else {
    // Columns in [first_col, first_col + local_cols) go to the diagonal block (as
    // local indices), the others to the off-diagonal block (global indices).
    // A row's columns are sorted, so its diagonal-block columns are one run
    // [lo, hi): the blocks are sized first, then filled run by run.
    OwnedRows& d = storage->diagonal;
    OwnedRows& o = storage->off_diagonal;
    const PetscInt last_col = first_col + local_cols;
    d.row_ptr.resize(static_cast<std::size_t>(local_rows) + 1);
    o.row_ptr.resize(static_cast<std::size_t>(local_rows) + 1);
    d.row_ptr[0] = o.row_ptr[0] = 0;
    std::vector<PetscInt> run(2 * static_cast<std::size_t>(local_rows));
    for (PetscInt r = 0; r < local_rows; ++r) {
      PetscInt lo = rows.row_ptr[r], hi;
      while (lo < rows.row_ptr[r + 1] && rows.cols[lo] < first_col) ++lo;
      hi = lo;
      while (hi < rows.row_ptr[r + 1] && rows.cols[hi] < last_col) ++hi;
      run[2 * r] = lo, run[2 * r + 1] = hi;
      d.row_ptr[r + 1] = d.row_ptr[r] + (hi - lo);
      o.row_ptr[r + 1] = o.row_ptr[r] + (rows.row_ptr[r + 1] - rows.row_ptr[r]) - (hi - lo);
    }
    d.cols.resize(static_cast<std::size_t>(d.row_ptr[local_rows]));
    o.cols.resize(static_cast<std::size_t>(o.row_ptr[local_rows]));
    const bool zeros = rows.vals.empty();
    d.vals.resize(d.cols.size(), 0.0);
    o.vals.resize(o.cols.size(), 0.0);
    for (PetscInt r = 0; r < local_rows; ++r) {
      const PetscInt lo = run[2 * r], hi = run[2 * r + 1];
      PetscInt od = o.row_ptr[r], dd = d.row_ptr[r];
      for (PetscInt k = rows.row_ptr[r]; k < lo; ++k, ++od) {
        o.cols[od] = rows.cols[k];
        if (!zeros) o.vals[od] = rows.vals[k];
      }
      for (PetscInt k = lo; k < hi; ++k, ++dd) {
        d.cols[dd] = rows.cols[k] - first_col;
        if (!zeros) d.vals[dd] = rows.vals[k];
      }
      for (PetscInt k = hi; k < rows.row_ptr[r + 1]; ++k, ++od) {
        o.cols[od] = rows.cols[k];
        if (!zeros) o.vals[od] = rows.vals[k];
      }
    }
    WARPFEM_PETSC_CHECK(MatCreateMPIAIJWithSplitArrays(
        comm, local_rows, local_cols, global_rows, global_cols, d.row_ptr.data(), d.cols.data(),
        d.vals.data(), o.row_ptr.data(), o.cols.data(), o.vals.data(), A.out()));
  }
  attach(A.get(), std::move(storage));
  return A;
}

}  // namespace warpfem::petsc
