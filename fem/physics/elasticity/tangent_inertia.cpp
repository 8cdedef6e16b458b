#include "fem/physics/elasticity/tangent_inertia.hpp"

#include <cmath>

#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"

namespace warpfem::fem {

std::optional<TangentStability> tangent_stability(Mat J, Vec start, int iterations) {
  MatType type = nullptr;
  WARPFEM_PETSC_CHECK(MatGetType(J, &type));
  PetscBool have_solver = PETSC_FALSE, have_type = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(
      MatSolverTypeGet(MATSOLVERMUMPS, type, MAT_FACTOR_CHOLESKY, &have_solver, &have_type, nullptr));
  if (!have_solver || !have_type) return std::nullopt;
  petsc::Matrix factor;
  WARPFEM_PETSC_CHECK(MatGetFactor(J, MATSOLVERMUMPS, MAT_FACTOR_CHOLESKY, factor.out()));
  // Inertia needs MUMPS's symmetric-indefinite mode (LDLᵀ, PETSc's default for Cholesky of AIJ),
  // null pivot detection (the zero count), and in parallel no ScaLAPACK root node.
  WARPFEM_PETSC_CHECK(MatMumpsSetIcntl(factor.get(), 24, 1));
  WARPFEM_PETSC_CHECK(MatMumpsSetIcntl(factor.get(), 13, 1));
  petsc::IndexSet row_order, column_order;
  WARPFEM_PETSC_CHECK(MatGetOrdering(J, MATORDERINGNATURAL, row_order.out(), column_order.out()));
  MatFactorInfo info;
  WARPFEM_PETSC_CHECK(MatFactorInfoInitialize(&info));
  WARPFEM_PETSC_CHECK(MatCholeskyFactorSymbolic(factor.get(), J, row_order.get(), &info));
  WARPFEM_PETSC_CHECK(MatCholeskyFactorNumeric(factor.get(), J, &info));
  MatFactorError error = MAT_FACTOR_NOERROR;
  WARPFEM_PETSC_CHECK(MatFactorGetError(factor.get(), &error));
  if (error != MAT_FACTOR_NOERROR) return std::nullopt;
  TangentStability s;
  WARPFEM_PETSC_CHECK(MatGetInertia(factor.get(), &s.negative, &s.zero, &s.positive));
  if (s.zero > 0) return s;

  // Inverse iteration x ← J⁻¹x / |J⁻¹x|; the Rayleigh quotient xᵀJx converges to the
  // eigenvalue nearest zero (with the factors already at hand, each step is two triangular solves).
  petsc::Vector x, y;
  WARPFEM_PETSC_CHECK(VecDuplicate(start, x.out()));
  WARPFEM_PETSC_CHECK(VecDuplicate(start, y.out()));
  WARPFEM_PETSC_CHECK(VecCopy(start, x.get()));
  PetscReal norm = 0;
  WARPFEM_PETSC_CHECK(VecNormalize(x.get(), &norm));
  if (norm == 0) return s;
  for (int k = 0; k < iterations; ++k) {
    WARPFEM_PETSC_CHECK(MatSolve(factor.get(), x.get(), y.get()));
    WARPFEM_PETSC_CHECK(VecNormalize(y.get(), &norm));
    if (!(norm > 0) || !std::isfinite(norm)) break;
    std::swap(x, y);
  }
  WARPFEM_PETSC_CHECK(MatMult(J, x.get(), y.get()));
  WARPFEM_PETSC_CHECK(VecDot(x.get(), y.get(), &s.eigenvalue_nearest_zero));
  return s;
}

}  // namespace warpfem::fem
