#include "multigrid/chebyshev_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/petsc/check.hpp"

namespace warpfem::multigrid {
namespace {

/// Adds Σ_j |a_ij| of every row of the sequential AIJ `block` to `sum` and, if
/// `diagonal` is given, records the entry in column r of row r there.
void accumulate(Mat block, std::vector<double>& sum, std::vector<double>* diagonal) {
  PetscInt rows = 0;
  PetscBool done = PETSC_FALSE;
  const PetscInt *ia = nullptr, *ja = nullptr;
  WARPFEM_PETSC_CHECK(MatGetRowIJ(block, 0, PETSC_FALSE, PETSC_FALSE, &rows, &ia, &ja, &done));
  require(done == PETSC_TRUE, "jacobi_gershgorin_bound: cannot read the matrix rows");
  const PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(MatSeqAIJGetArrayRead(block, &a));
  for (PetscInt r = 0; r < rows; ++r)
    for (PetscInt k = ia[r]; k < ia[r + 1]; ++k) {
      sum[static_cast<std::size_t>(r)] += std::abs(a[k]);
      if (diagonal && ja[k] == r) (*diagonal)[static_cast<std::size_t>(r)] = a[k];
    }
  WARPFEM_PETSC_CHECK(MatSeqAIJRestoreArrayRead(block, &a));
  WARPFEM_PETSC_CHECK(MatRestoreRowIJ(block, 0, PETSC_FALSE, PETSC_FALSE, &rows, &ia, &ja, &done));
}

}  // namespace

double jacobi_gershgorin_bound(Mat A) {
  PetscInt begin = 0, end = 0;
  WARPFEM_PETSC_CHECK(MatGetOwnershipRange(A, &begin, &end));
  const std::size_t rows = static_cast<std::size_t>(end - begin);
  std::vector<double> sum(rows, 0.0), diagonal(rows, 0.0);
  PetscBool mpi = PETSC_FALSE, seq = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A), MATMPIAIJ, &mpi));
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A), MATSEQAIJ, &seq));
  if (seq) {
    accumulate(A, sum, &diagonal);
  } else if (mpi) {
    Mat diag_block = nullptr, off_block = nullptr;
    const PetscInt* garray = nullptr;
    WARPFEM_PETSC_CHECK(MatMPIAIJGetSeqAIJ(A, &diag_block, &off_block, &garray));
    accumulate(diag_block, sum, &diagonal);  // local columns: the diagonal is column r
    accumulate(off_block, sum, nullptr);
  } else {  // any other type, row by row
    for (PetscInt r = begin; r < end; ++r) {
      PetscInt n = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      WARPFEM_PETSC_CHECK(MatGetRow(A, r, &n, &cols, &vals));
      for (PetscInt k = 0; k < n; ++k) {
        sum[static_cast<std::size_t>(r - begin)] += std::abs(vals[k]);
        if (cols[k] == r) diagonal[static_cast<std::size_t>(r - begin)] = vals[k];
      }
      WARPFEM_PETSC_CHECK(MatRestoreRow(A, r, &n, &cols, &vals));
    }
  }
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  return jacobi_gershgorin_bound(comm, diagonal.data(), sum.data(), static_cast<PetscInt>(rows), begin);
}

double jacobi_gershgorin_bound(MPI_Comm comm, const double* diagonal, const double* row_abs_sum,
                               PetscInt rows, PetscInt first_row) {
  // local[0]: the bound over this rank's rows; local[1]: whether one of them has
  // no positive diagonal. Reduced together before anyone throws, so a rank
  // with a bad row cannot leave the others waiting in the reduction.
  double local[2] = {0.0, 0.0};
  PetscInt bad = rows;
  for (PetscInt r = 0; r < rows; ++r) {
    if (!(diagonal[r] > 0) || !std::isfinite(diagonal[r])) {
      bad = std::min(bad, r);
      continue;
    }
    local[0] = std::max(local[0], row_abs_sum[r] / diagonal[r]);
  }
  local[1] = bad < rows ? 1.0 : 0.0;
  double global[2] = {0.0, 0.0};
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MAX, comm);
  if (global[1] > 0)
    throw Error(
        "Chebyshev–Jacobi smoothing needs a positive diagonal; " +
            (bad < rows ? "row " + std::to_string(first_row + bad) + " has " + std::to_string(diagonal[bad])
                        : std::string("a row on another rank has none")),
        {.file = "",
         .key_path = "solver.multigrid.chebyshev_bounds",
         .hint = "the operator is not symmetric positive definite; check the boundary conditions"});
  return global[0];
}

}  // namespace warpfem::multigrid
