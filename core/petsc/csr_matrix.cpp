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
    // [lo, hi): the blocks' row pointers are counted first, then the runs are
    // appended (no zero-filled arrays to overwrite).
    OwnedRows& d = storage->diagonal;
    OwnedRows& o = storage->off_diagonal;
    const PetscInt last_col = first_col + local_cols;
    const auto diagonal_run = [&](PetscInt r) {
      PetscInt lo = rows.row_ptr[r];
      while (lo < rows.row_ptr[r + 1] && rows.cols[lo] < first_col) ++lo;
      PetscInt hi = lo;
      while (hi < rows.row_ptr[r + 1] && rows.cols[hi] < last_col) ++hi;
      return std::pair{lo, hi};
    };
    d.row_ptr.resize(static_cast<std::size_t>(local_rows) + 1);
    o.row_ptr.resize(static_cast<std::size_t>(local_rows) + 1);
    d.row_ptr[0] = o.row_ptr[0] = 0;
    for (PetscInt r = 0; r < local_rows; ++r) {
      const auto [lo, hi] = diagonal_run(r);
      d.row_ptr[r + 1] = d.row_ptr[r] + (hi - lo);
      o.row_ptr[r + 1] = o.row_ptr[r] + (rows.row_ptr[r + 1] - rows.row_ptr[r]) - (hi - lo);
    }
    const bool zeros = rows.vals.empty();
    d.cols.reserve(static_cast<std::size_t>(d.row_ptr[local_rows]));
    o.cols.reserve(static_cast<std::size_t>(o.row_ptr[local_rows]));
    if (zeros) {
      d.vals.assign(static_cast<std::size_t>(d.row_ptr[local_rows]), 0.0);
      o.vals.assign(static_cast<std::size_t>(o.row_ptr[local_rows]), 0.0);
    } else {
      d.vals.reserve(static_cast<std::size_t>(d.row_ptr[local_rows]));
      o.vals.reserve(static_cast<std::size_t>(o.row_ptr[local_rows]));
    }
    const auto append = [&](OwnedRows& block, PetscInt from, PetscInt to, PetscInt shift) {
      for (PetscInt k = from; k < to; ++k) {
        block.cols.push_back(rows.cols[k] - shift);
        if (!zeros) block.vals.push_back(rows.vals[k]);
      }
    };
    for (PetscInt r = 0; r < local_rows; ++r) {
      const auto [lo, hi] = diagonal_run(r);
      append(o, rows.row_ptr[r], lo, 0);
      append(d, lo, hi, first_col);
      append(o, hi, rows.row_ptr[r + 1], 0);
    }
    WARPFEM_PETSC_CHECK(MatCreateMPIAIJWithSplitArrays(
        comm, local_rows, local_cols, global_rows, global_cols, d.row_ptr.data(), d.cols.data(),
        d.vals.data(), o.row_ptr.data(), o.cols.data(), o.vals.data(), A.out()));
  }
  attach(A.get(), std::move(storage));
  return A;
}

}  // namespace warpfem::petsc
