#include "core/petsc/matrix_assembler.hpp"

#include "core/error.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::petsc {
namespace {
void get_rows(Mat block, PetscInt owned, const PetscInt** i, const PetscInt** j, PetscScalar** v) {
  PetscInt rows = 0;
  PetscBool done = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(MatGetRowIJ(block, 0, PETSC_FALSE, PETSC_FALSE, &rows, i, j, &done));
  require(done == PETSC_TRUE && rows == owned, "MatrixAssembler: cannot access the matrix rows");
  WARPFEM_PETSC_CHECK(MatSeqAIJGetArray(block, v));
}
void restore_rows(Mat block, const PetscInt** i, const PetscInt** j, PetscScalar** v) {
  WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArray(block, v));
  PetscInt rows = 0;
  PetscBool done = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(MatRestoreRowIJ(block, 0, PETSC_FALSE, PETSC_FALSE, &rows, i, j, &done));
}
}  // namespace

MatrixAssembler::MatrixAssembler(Mat A, Vec b) : A_(A), Ad_(A), bvec_(b) {
  int size = 1;
  MPI_Comm_size(PetscObjectComm(reinterpret_cast<PetscObject>(A)), &size);
  serial_ = size == 1;
  PetscInt end = 0;
  WARPFEM_PETSC_CHECK(MatGetOwnershipRange(A, &begin_, &end));
  owned_ = end - begin_;
  WARPFEM_PETSC_CHECK(MatZeroEntries(A));
  if (!serial_) WARPFEM_PETSC_CHECK(MatMPIAIJGetSeqAIJ(A, &Ad_, &Ao_, &garray_));
  get_rows(Ad_, owned_, &ia_, &ja_, &a_);
  if (!serial_) get_rows(Ao_, owned_, &ia_o_, &ja_o_, &ao_);
  if (bvec_) {
    WARPFEM_PETSC_CHECK(VecSet(bvec_, 0.0));
    WARPFEM_PETSC_CHECK(VecGetArray(bvec_, &b_));
  }
}

MatrixAssembler::~MatrixAssembler() {
  if (!finished_) {  // an exception left the assembly: give the arrays back, without throwing
    try {
      release();
    } catch (...) {
    }
  }
}

void MatrixAssembler::release() {
  if (b_) WARPFEM_PETSC_CHECK(VecRestoreArray(bvec_, &b_));
  b_ = nullptr;
  if (a_) restore_rows(Ad_, &ia_, &ja_, &a_);
  a_ = nullptr;
  if (ao_) restore_rows(Ao_, &ia_o_, &ja_o_, &ao_);
  ao_ = nullptr;
}

void MatrixAssembler::add_ghost_row(int n, const PetscInt* dofs, int r, const double* ke, const double* fe) {
  for (int k = 0; k < n; ++k) {
    ghost_rows_.push_back(dofs[r]);
    ghost_cols_.push_back(dofs[k]);
    ghost_vals_.push_back(ke[r * n + k]);
  }
  if (fe) {
    ghost_b_rows_.push_back(dofs[r]);
    ghost_b_vals_.push_back(fe[r]);
  }
}

void MatrixAssembler::set_diagonal(PetscInt global_row, double value) {
  const PetscInt row = global_row - begin_;
  require(row >= 0 && row < owned_, "MatrixAssembler::set_diagonal: the row is not owned here");
  PetscInt j = ia_[row];
  while (ja_[j] != row) ++j;  // serial: begin = 0; MPI: the diagonal block's columns are local
  a_[j] = value;
}

void MatrixAssembler::finish() {
  finished_ = true;
  release();
  for (std::size_t g = 0; g < ghost_rows_.size(); ++g)
    WARPFEM_PETSC_CHECK(
        MatSetValues(A_, 1, &ghost_rows_[g], 1, &ghost_cols_[g], &ghost_vals_[g], ADD_VALUES));
  if (bvec_ && !ghost_b_rows_.empty())
    WARPFEM_PETSC_CHECK(VecSetValues(bvec_, static_cast<PetscInt>(ghost_b_rows_.size()), ghost_b_rows_.data(),
                                     ghost_b_vals_.data(), ADD_VALUES));
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY));
  if (bvec_) {
    WARPFEM_PETSC_CHECK(VecAssemblyBegin(bvec_));
    WARPFEM_PETSC_CHECK(VecAssemblyEnd(bvec_));
  }
}

}  // namespace warpfem::petsc
