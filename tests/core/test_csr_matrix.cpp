// petsc::adopt_owned_rows: PETSc uses our compressed rows as they are, on any
// number of ranks (this file also runs under mpiexec -n 2 as test_mpi_core):
// products and transposed products equal the ones computed from the rows.

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/csr_matrix.hpp"

using namespace warpfem;

namespace {
constexpr PetscInt kRows = 12, kCols = 7;

/// A prolongation-like pattern: row i reads columns i/2 and i/2 + 1 (if any).
std::vector<std::pair<PetscInt, double>> row_entries(PetscInt i) {
  std::vector<std::pair<PetscInt, double>> e{{i / 2, 0.5 + 0.01 * i}};
  if (i / 2 + 1 < kCols) e.push_back({i / 2 + 1, 0.25 - 0.01 * i});
  return e;
}
}  // namespace

TEST(CsrMatrix, AdoptedRowsMultiplyAsTheyRead) {
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const PetscInt r0 = kRows * rank / size, r1 = kRows * (rank + 1) / size;
  const PetscInt c0 = kCols * rank / size, c1 = kCols * (rank + 1) / size;
  petsc::OwnedRows rows;
  rows.row_ptr.push_back(0);
  for (PetscInt i = r0; i < r1; ++i) {
    for (const auto& [j, v] : row_entries(i)) {
      rows.cols.push_back(j);
      rows.vals.push_back(v);
    }
    rows.row_ptr.push_back(static_cast<PetscInt>(rows.cols.size()));
  }
  petsc::Matrix A = petsc::adopt_owned_rows(PETSC_COMM_WORLD, std::move(rows), c1 - c0, c0, kRows, kCols);
  PetscInt m = 0, n = 0;
  WARPFEM_PETSC_CHECK(MatGetSize(A.get(), &m, &n));
  EXPECT_EQ(m, kRows);
  EXPECT_EQ(n, kCols);

  // y = A x with x_j = j + 1.
  petsc::Vector x, y;
  WARPFEM_PETSC_CHECK(MatCreateVecs(A.get(), x.out(), y.out()));
  for (PetscInt j = c0; j < c1; ++j) WARPFEM_PETSC_CHECK(VecSetValue(x.get(), j, j + 1.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(x.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(x.get()));
  WARPFEM_PETSC_CHECK(MatMult(A.get(), x.get(), y.get()));
  const PetscScalar* ya = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(y.get(), &ya));
  for (PetscInt i = r0; i < r1; ++i) {
    double expected = 0;
    for (const auto& [j, v] : row_entries(i)) expected += v * (j + 1.0);
    EXPECT_NEAR(ya[i - r0], expected, 1e-14) << "row " << i;
  }
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(y.get(), &ya));

  // x = Aᵀ 1: column sums (what PCMG's restriction computes).
  WARPFEM_PETSC_CHECK(VecSet(y.get(), 1.0));
  WARPFEM_PETSC_CHECK(MatMultTranspose(A.get(), y.get(), x.get()));
  const PetscScalar* xa = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(x.get(), &xa));
  for (PetscInt j = c0; j < c1; ++j) {
    double expected = 0;
    for (PetscInt i = 0; i < kRows; ++i)
      for (const auto& [jj, v] : row_entries(i))
        if (jj == j) expected += v;
    EXPECT_NEAR(xa[j - c0], expected, 1e-14) << "column " << j;
  }
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(x.get(), &xa));
}

// A pattern without values (empty vals) becomes a matrix of zeros with exactly
// these columns, also when a row has columns of other ranks on both sides of
// its own (the diagonal block is a run in the middle of the sorted row).
TEST(CsrMatrix, PatternWithoutValuesKeepsEveryColumn) {
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const PetscInt r0 = kRows * rank / size, r1 = kRows * (rank + 1) / size;
  const PetscInt c0 = kRows * rank / size, c1 = kRows * (rank + 1) / size;  // square
  const auto columns = [](PetscInt i) {
    std::vector<PetscInt> c{0, i, kRows - 1};
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    return c;
  };
  petsc::OwnedRows rows;
  rows.row_ptr.push_back(0);
  for (PetscInt i = r0; i < r1; ++i) {
    for (const PetscInt j : columns(i)) rows.cols.push_back(j);
    rows.row_ptr.push_back(static_cast<PetscInt>(rows.cols.size()));
  }
  petsc::Matrix A = petsc::adopt_owned_rows(PETSC_COMM_WORLD, std::move(rows), c1 - c0, c0, kRows, kRows);
  for (PetscInt i = r0; i < r1; ++i) {
    PetscInt n = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    WARPFEM_PETSC_CHECK(MatGetRow(A.get(), i, &n, &cols, &vals));
    const std::vector<PetscInt> got(cols, cols + n);
    for (PetscInt k = 0; k < n; ++k) EXPECT_EQ(vals[k], 0.0) << "row " << i;
    WARPFEM_PETSC_CHECK(MatRestoreRow(A.get(), i, &n, &cols, &vals));
    EXPECT_EQ(got, columns(i)) << "row " << i;
  }
  // Mismatched values are refused (before anything collective, so on every rank).
  petsc::OwnedRows bad;
  bad.row_ptr = {0, 1};
  bad.cols = {0};
  bad.vals = {1.0, 2.0};
  EXPECT_THROW(petsc::adopt_owned_rows(PETSC_COMM_WORLD, std::move(bad), kRows, 0, 1, kRows), Error);
}

// Rows already split into PETSc's two blocks: the same matrix as adopting the
// unsplit rows (here: the identity with the last global column appended to
// every row as a coupling to another rank), and blocks of different row counts
// are refused on every rank.
TEST(CsrMatrix, SplitRowsAreAdoptedAsTheyAreGiven) {
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const PetscInt r0 = kRows * rank / size, r1 = kRows * (rank + 1) / size;
  petsc::OwnedRows diagonal, off;
  diagonal.row_ptr.push_back(0);
  off.row_ptr.push_back(0);
  for (PetscInt i = r0; i < r1; ++i) {
    diagonal.cols.push_back(i - r0);  // local column
    diagonal.vals.push_back(2.0);
    if (kRows - 1 >= r1) {  // the last column belongs to another rank
      off.cols.push_back(kRows - 1);
      off.vals.push_back(-1.0);
    }
    diagonal.row_ptr.push_back(static_cast<PetscInt>(diagonal.cols.size()));
    off.row_ptr.push_back(static_cast<PetscInt>(off.cols.size()));
  }
  petsc::Matrix A =
      petsc::adopt_split_rows(PETSC_COMM_WORLD, std::move(diagonal), std::move(off), r1 - r0, kRows, kRows);
  for (PetscInt i = r0; i < r1; ++i) {
    PetscInt n = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    WARPFEM_PETSC_CHECK(MatGetRow(A.get(), i, &n, &cols, &vals));
    std::vector<std::pair<PetscInt, double>> got;
    for (PetscInt k = 0; k < n; ++k) got.emplace_back(cols[k], vals[k]);
    WARPFEM_PETSC_CHECK(MatRestoreRow(A.get(), i, &n, &cols, &vals));
    std::vector<std::pair<PetscInt, double>> want{{i, 2.0}};
    if (kRows - 1 >= r1) want.emplace_back(kRows - 1, -1.0);
    EXPECT_EQ(got, want) << "row " << i;
  }
  petsc::OwnedRows one, two;
  one.row_ptr = {0};
  two.row_ptr = {0, 0};
  EXPECT_THROW(petsc::adopt_split_rows(PETSC_COMM_WORLD, std::move(one), std::move(two), 0, kRows, kRows),
               Error);
}

// Inodes (runs of rows with the same columns) are searched for by default and
// skipped on request, and the request leaves PETSc's options as they were:
// 2 x 2 diagonal blocks give kRows / 2 inodes of two rows each, or none.
TEST(CsrMatrix, InodeSearchIsSkippedOnlyWhenAsked) {
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const PetscInt r0 = 2 * ((kRows / 2) * rank / size), r1 = 2 * ((kRows / 2) * (rank + 1) / size);
  const auto pairs = [&] {
    petsc::OwnedRows rows;
    rows.row_ptr.push_back(0);
    for (PetscInt i = r0; i < r1; ++i) {
      const PetscInt first = i - i % 2;
      rows.cols.insert(rows.cols.end(), {first, first + 1});
      rows.vals.insert(rows.vals.end(), {2.0 + i, -1.0});
      rows.row_ptr.push_back(static_cast<PetscInt>(rows.cols.size()));
    }
    return rows;
  };
  const auto inodes = [&](const petsc::Matrix& A) {
    Mat block = A.get();
    if (size > 1) WARPFEM_PETSC_CHECK(MatMPIAIJGetSeqAIJ(A.get(), &block, nullptr, nullptr));
    PetscInt count = 0, limit = 0;
    PetscInt* sizes = nullptr;
    WARPFEM_PETSC_CHECK(MatInodeGetInodeSizes(block, &count, &sizes, &limit));
    return count;
  };
  const PetscInt local = r1 - r0;
  const petsc::Matrix searched = petsc::adopt_owned_rows(PETSC_COMM_WORLD, pairs(), local, r0, kRows, kRows);
  EXPECT_EQ(inodes(searched), local / 2);
  const petsc::Matrix skipped =
      petsc::adopt_owned_rows(PETSC_COMM_WORLD, pairs(), local, r0, kRows, kRows, {.inodes = false});
  EXPECT_EQ(inodes(skipped), 0);
  PetscBool left = PETSC_TRUE;
  WARPFEM_PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, "-mat_no_inode", &left));
  EXPECT_FALSE(left) << "the temporary -mat_no_inode stayed in the options database";
  const petsc::Matrix searched_again =
      petsc::adopt_owned_rows(PETSC_COMM_WORLD, pairs(), local, r0, kRows, kRows);
  EXPECT_EQ(inodes(searched_again), local / 2);
}
