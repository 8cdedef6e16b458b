// Stability of an equilibrium from its tangent: inertia and lowest eigenvalue (MUMPS LDLᵀ).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"
#include "fem/physics/elasticity/tangent_inertia.hpp"

using namespace warpfem;

namespace {

/// The n × n matrix tridiag(-1, 2, -1) + shift·I (eigenvalues 2 − 2 cos(kπ/(n+1)) + shift).
petsc::Matrix laplacian(PetscInt n, double shift) {
  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(MatCreateSeqAIJ(PETSC_COMM_SELF, n, n, 3, nullptr, A.out()));
  for (PetscInt i = 0; i < n; ++i) {
    WARPFEM_PETSC_CHECK(MatSetValue(A.get(), i, i, 2.0 + shift, INSERT_VALUES));
    if (i > 0) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), i, i - 1, -1.0, INSERT_VALUES));
    if (i + 1 < n) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), i, i + 1, -1.0, INSERT_VALUES));
  }
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A.get(), MAT_FINAL_ASSEMBLY));
  return A;
}

petsc::Vector start_vector(PetscInt n) {
  petsc::Vector v;
  WARPFEM_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, n, v.out()));
  for (PetscInt i = 0; i < n; ++i)
    WARPFEM_PETSC_CHECK(
        VecSetValue(v.get(), i, std::sin(12.9898 * static_cast<double>(i) + 0.5), INSERT_VALUES));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(v.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(v.get()));
  return v;
}

double eigenvalue(PetscInt n, int k, double shift) {
  return 2 - 2 * std::cos(k * std::numbers::pi / static_cast<double>(n + 1)) + shift;
}

}  // namespace

TEST(TangentStability, PositiveDefiniteTangentHasNoNegativeEigenvalueAndItsLowestIsFound) {
  const PetscInt n = 40;
  const petsc::Matrix A = laplacian(n, 0.0);
  const petsc::Vector x = start_vector(n);
  const auto s = fem::tangent_stability(A.get(), x.get(), 200);
  if (!s) GTEST_SKIP() << "PETSc without MUMPS";
  EXPECT_EQ(s->negative, 0);
  EXPECT_EQ(s->zero, 0);
  EXPECT_EQ(s->positive, n);
  EXPECT_NEAR(s->eigenvalue_nearest_zero, eigenvalue(n, 1, 0.0), 1e-6 * eigenvalue(n, 1, 0.0));
}

TEST(TangentStability, CountsTheNegativeEigenvaluesOfAnIndefiniteTangent) {
  // A shift between λ_2 and λ_3 leaves exactly the two lowest eigenvalues negative.
  const PetscInt n = 40;
  const double shift = -(0.6 * eigenvalue(n, 2, 0.0) + 0.4 * eigenvalue(n, 3, 0.0));
  const petsc::Matrix A = laplacian(n, shift);
  const petsc::Vector x = start_vector(n);
  const auto s = fem::tangent_stability(A.get(), x.get(), 200);
  if (!s) GTEST_SKIP() << "PETSc without MUMPS";
  EXPECT_EQ(s->negative, 2);
  EXPECT_EQ(s->positive, n - 2);
  // Inverse iteration finds the eigenvalue nearest zero, the (negative) second one.
  const double l2 = eigenvalue(n, 2, shift), l3 = eigenvalue(n, 3, shift);
  EXPECT_NEAR(s->eigenvalue_nearest_zero, l2, 1e-6 * std::abs(l2));
  EXPECT_LT(l2, 0);
  EXPECT_GT(l3, 0);
}
