#include "core/petsc/csr_matrix.hpp"

#include <memory>
#include <utility>

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
  if (size == 1) {
    storage->diagonal = std::move(rows);
    OwnedRows& d = storage->diagonal;
    WARPFEM_PETSC_CHECK(MatCreateSeqAIJWithArrays(comm, local_rows, local_cols, d.row_ptr.data(),
                                                  d.cols.data(), d.vals.data(), A.out()));
  } else {
    // Columns in [first_col, first_col + local_cols) go to the diagonal block (as
    // local indices), the others to the off-diagonal block (global indices).
    OwnedRows& d = storage->diagonal;
    OwnedRows& o = storage->off_diagonal;
    d.row_ptr.assign(static_cast<std::size_t>(local_rows) + 1, 0);
    o.row_ptr.assign(static_cast<std::size_t>(local_rows) + 1, 0);
    d.cols.reserve(rows.cols.size());  // most columns are local
    d.vals.reserve(rows.vals.size());
    for (PetscInt r = 0; r < local_rows; ++r) {
      for (PetscInt k = rows.row_ptr[r]; k < rows.row_ptr[r + 1]; ++k) {
        const PetscInt c = rows.cols[k] - first_col;
        OwnedRows& block = c >= 0 && c < local_cols ? d : o;
        block.cols.push_back(&block == &d ? c : rows.cols[k]);
        block.vals.push_back(rows.vals[k]);
      }
      d.row_ptr[r + 1] = static_cast<PetscInt>(d.cols.size());
      o.row_ptr[r + 1] = static_cast<PetscInt>(o.cols.size());
    }
    WARPFEM_PETSC_CHECK(MatCreateMPIAIJWithSplitArrays(
        comm, local_rows, local_cols, global_rows, global_cols, d.row_ptr.data(), d.cols.data(),
        d.vals.data(), o.row_ptr.data(), o.cols.data(), o.vals.data(), A.out()));
  }
  attach(A.get(), std::move(storage));
  return A;
}

}  // namespace warpfem::petsc
