#pragma once
// Adds element matrices and vectors into a PETSc AIJ matrix whose sparsity
// pattern already holds every entry (e.g. adopted with adopt_owned_rows):
// entries of owned rows go straight into the matrix's compressed arrays
// (serial: the matrix; MPI: its diagonal and off-diagonal blocks), entries of
// rows owned by other ranks through MatSetValues / VecSetValues at finish().
//
//   MatrixAssembler a(A, b);            // zeroes A and b
//   for each cell: a.add(n, global_dofs, ke, fe);
//   a.set_diagonal(row, 1.0);           // e.g. eliminated Dirichlet rows
//   a.finish();                         // restores arrays, assembles A and b

#include <petscmat.h>

#include <vector>

namespace warpfem::petsc {

class MatrixAssembler {
 public:
  /// `A`'s pattern must contain every entry that add() reaches; `b` may be null.
  MatrixAssembler(Mat A, Vec b);
  ~MatrixAssembler();
  MatrixAssembler(const MatrixAssembler&) = delete;
  MatrixAssembler& operator=(const MatrixAssembler&) = delete;

  /// Adds the n x n row-major `ke` at rows/columns `dofs` (global) and `fe` (may be null) at rows `dofs`.
  [[gnu::always_inline]] void add(int n, const PetscInt* dofs, const double* ke, const double* fe) {
    // The members in locals: the compiler then need not reload them after each store.
    const PetscInt begin = begin_, owned = owned_;
    const PetscInt *ia = ia_, *ja = ja_;
    PetscScalar* a = a_;
    for (int r = 0; r < n; ++r) {
      const PetscInt row = dofs[r] - begin;
      if (row < 0 || row >= owned) {
        add_ghost_row(n, dofs, r, ke, fe);
        continue;
      }
      if (fe) b_[row] += fe[r];
      const PetscInt* cols = ja + ia[row];
      PetscScalar* vals = a + ia[row];
      if (serial_) {
        for (int k = 0; k < n; ++k) {
          PetscInt j = 0;
          while (cols[j] != dofs[k]) ++j;  // rows hold ~7-20 entries: a linear scan beats bisection
          vals[j] += ke[r * n + k];
        }
      } else {
        for (int k = 0; k < n; ++k) {
          const PetscInt col = dofs[k] - begin;  // the diagonal block's columns are local
          if (col >= 0 && col < owned) {
            PetscInt j = 0;
            while (cols[j] != col) ++j;
            vals[j] += ke[r * n + k];
          } else {  // a column of another rank (rows along the interface only)
            PetscInt j = ia_o_[row];
            while (garray_[ja_o_[j]] != dofs[k]) ++j;
            ao_[j] += ke[r * n + k];
          }
        }
      }
    }
  }
  /// Adds `fe` at the global rows `dofs` of the right-hand side only.
  void add_vector(int n, const PetscInt* dofs, const double* fe) {
    for (int r = 0; r < n; ++r) {
      const PetscInt row = dofs[r] - begin_;
      if (row >= 0 && row < owned_) {
        b_[row] += fe[r];
      } else {
        ghost_b_rows_.push_back(dofs[r]);
        ghost_b_vals_.push_back(fe[r]);
      }
    }
  }
  /// Sets the diagonal entry of the owned global row `row` (an entry of the pattern).
  void set_diagonal(PetscInt row, double value);
  /// Restores the arrays, adds the other ranks' rows and assembles A and b. Collective.
  void finish();

 private:
  void add_ghost_row(int n, const PetscInt* dofs, int r, const double* ke, const double* fe);
  void release();

  Mat A_, Ad_ = nullptr, Ao_ = nullptr;
  Vec bvec_;
  bool serial_ = true, finished_ = false;
  PetscInt begin_ = 0, owned_ = 0;
  const PetscInt *ia_ = nullptr, *ja_ = nullptr, *ia_o_ = nullptr, *ja_o_ = nullptr, *garray_ = nullptr;
  PetscScalar *a_ = nullptr, *ao_ = nullptr, *b_ = nullptr;
  std::vector<PetscInt> ghost_rows_, ghost_cols_, ghost_b_rows_;
  std::vector<PetscScalar> ghost_vals_, ghost_b_vals_;
};

}  // namespace warpfem::petsc
