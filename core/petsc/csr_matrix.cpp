#include "core/petsc/csr_matrix.hpp"

#include <memory>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/prefault.hpp"

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

/// PETSc fixes whether a SeqAIJ matrix searches for inodes when the matrix is
/// created, from the options database (`-mat_no_inode`), and the
/// MatCreate*WithArrays calls assemble at once, before MatSetOption could
/// switch the search off. So the option is set for the duration of the
/// creation, unless the user's options already name it.
class InodeSearchOff {
 public:
  explicit InodeSearchOff(bool active) {
    if (!active) return;
    PetscBool named = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, kOption, &named));
    if (named) return;
    WARPFEM_PETSC_CHECK(PetscOptionsSetValue(nullptr, kOption, "true"));
    set_ = true;
  }
  ~InodeSearchOff() {
    if (set_) PetscOptionsClearValue(nullptr, kOption);
  }
  InodeSearchOff(const InodeSearchOff&) = delete;
  InodeSearchOff& operator=(const InodeSearchOff&) = delete;

 private:
  static constexpr const char* kOption = "-mat_no_inode";
  bool set_ = false;
};

}  // namespace

Matrix adopt_owned_rows(MPI_Comm comm, OwnedRows rows, PetscInt local_cols, PetscInt first_col,
                        PetscInt global_rows, PetscInt global_cols, const AdoptOptions& options) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const PetscInt local_rows = static_cast<PetscInt>(rows.row_ptr.size()) - 1;
  require(rows.vals.empty() || rows.vals.size() == rows.cols.size(),
          "adopt_owned_rows: " + std::to_string(rows.vals.size()) + " values for " +
              std::to_string(rows.cols.size()) + " columns");
  if (size > 1) {
    // Columns in [first_col, first_col + local_cols) go to the diagonal block (as
    // local indices), the others to the off-diagonal block (global indices). The
    // diagonal block is compacted in place in `rows`' own arrays (an entry moves
    // only towards the front), so the pattern is never copied; the off-diagonal
    // block (the interface) is small.
    OwnedRows off;
    off.row_ptr.assign(rows.row_ptr.size(), 0);
    const PetscInt last_col = first_col + local_cols;
    // Two call-free passes over raw pointers: count the interface entries, then
    // compact. With push_back inside the loop GCC kept the loop's counters in
    // memory, at several cycles per entry.
    PetscInt* const cols = rows.cols.data();
    PetscScalar* const vals = rows.vals.empty() ? nullptr : rows.vals.data();
    PetscInt* const row_ptr = rows.row_ptr.data();
    const PetscInt entries = row_ptr[local_rows] - row_ptr[0];
    PetscInt interface_entries = 0;
    for (PetscInt k = row_ptr[0]; k < row_ptr[local_rows]; ++k)
      interface_entries += cols[k] < first_col || cols[k] >= last_col;
    off.cols.resize(static_cast<std::size_t>(interface_entries));
    if (vals) off.vals.resize(static_cast<std::size_t>(interface_entries));
    PetscInt* const off_cols = off.cols.data();
    PetscScalar* const off_vals = off.vals.data();
    PetscInt* const off_row_ptr = off.row_ptr.data();
    PetscInt kept = 0, moved = 0, start = row_ptr[0];
    for (PetscInt r = 0; r < local_rows; ++r) {
      const PetscInt end = row_ptr[r + 1];
      for (PetscInt k = start; k < end; ++k) {
        const PetscInt col = cols[k];
        if (col >= first_col && col < last_col) [[likely]] {
          cols[kept] = col - first_col;
          if (vals) vals[kept] = vals[k];
          ++kept;
        } else {
          off_cols[moved] = col;
          if (vals) off_vals[moved] = vals[k];
          ++moved;
        }
      }
      row_ptr[r + 1] = kept;
      off_row_ptr[r + 1] = moved;
      start = end;
    }
    require(kept + moved == entries, "adopt_owned_rows: the split lost entries");
    rows.cols.resize(static_cast<std::size_t>(kept));
    if (vals) rows.vals.resize(static_cast<std::size_t>(kept));
    return adopt_split_rows(comm, std::move(rows), std::move(off), local_cols, global_rows, global_cols,
                            options);
  }
  if (rows.vals.empty()) resize_prefaulted(rows.vals, rows.cols.size());  // zeros
  auto storage = std::make_unique<Storage>();
  storage->diagonal = std::move(rows);
  OwnedRows& d = storage->diagonal;
  Matrix A;
  {
    const InodeSearchOff no_inodes(!options.inodes);
    WARPFEM_PETSC_CHECK(MatCreateSeqAIJWithArrays(comm, local_rows, local_cols, d.row_ptr.data(),
                                                  d.cols.data(), d.vals.data(), A.out()));
  }
  attach(A.get(), std::move(storage));
  return A;
}

Matrix adopt_split_rows(MPI_Comm comm, OwnedRows diagonal, OwnedRows off_diagonal, PetscInt local_cols,
                        PetscInt global_rows, PetscInt global_cols, const AdoptOptions& options) {
  const PetscInt local_rows = static_cast<PetscInt>(diagonal.row_ptr.size()) - 1;
  require(local_rows >= 0 && off_diagonal.row_ptr.size() == diagonal.row_ptr.size(),
          "adopt_split_rows: the diagonal and off-diagonal blocks have different row counts");
  for (OwnedRows* block : {&diagonal, &off_diagonal}) {
    if (block->vals.empty()) resize_prefaulted(block->vals, block->cols.size());  // zeros
    require(block->vals.size() == block->cols.size(),
            "adopt_split_rows: " + std::to_string(block->vals.size()) + " values for " +
                std::to_string(block->cols.size()) + " columns");
  }
  auto storage = std::make_unique<Storage>();
  storage->diagonal = std::move(diagonal);
  storage->off_diagonal = std::move(off_diagonal);
  OwnedRows& d = storage->diagonal;
  OwnedRows& o = storage->off_diagonal;
  Matrix A;
  {
    const InodeSearchOff no_inodes(!options.inodes);
    WARPFEM_PETSC_CHECK(MatCreateMPIAIJWithSplitArrays(
        comm, local_rows, local_cols, global_rows, global_cols, d.row_ptr.data(), d.cols.data(),
        d.vals.data(), o.row_ptr.data(), o.cols.data(), o.vals.data(), A.out()));
  }
  attach(A.get(), std::move(storage));
  return A;
}

}  // namespace warpfem::petsc
