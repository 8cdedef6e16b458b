// Gershgorin bounds for Chebyshev–Jacobi: an upper bound on the spectrum of
// D⁻¹A (never below it, so Chebyshev cannot amplify the top modes), tight for
// first-order stiffness matrices, and what the multigrid solver uses for them.
// Symmetric Gauss–Seidel's bound λmax(M⁻¹A) ≤ 1 for Chebyshev–SOR on one process.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "core/error.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/petsc/check.hpp"
#include "multigrid/chebyshev_bounds.hpp"
#include "multigrid/fused_chebyshev_jacobi.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "multigrid_fixtures.hpp"

using namespace warpfem;

namespace {

/// A small sequential matrix as a dense one.
MatrixX dense_copy(Mat A) {
  PetscInt n = 0;
  WARPFEM_PETSC_CHECK(MatGetSize(A, &n, nullptr));
  MatrixX dense = MatrixX::Zero(n, n);
  for (PetscInt r = 0; r < n; ++r) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    WARPFEM_PETSC_CHECK(MatGetRow(A, r, &nz, &cols, &vals));
    for (PetscInt k = 0; k < nz; ++k) dense(r, cols[k]) = vals[k];
    WARPFEM_PETSC_CHECK(MatRestoreRow(A, r, &nz, &cols, &vals));
  }
  return dense;
}

/// λmax(D⁻¹A) = λmax(D^{-1/2} A D^{-1/2}) of a small sequential matrix, densely.
double jacobi_lambda_max(Mat A) {
  const MatrixX dense = dense_copy(A);
  const VectorX s = dense.diagonal().cwiseSqrt().cwiseInverse();
  const MatrixX scaled = s.asDiagonal() * dense * s.asDiagonal();
  return Eigen::SelfAdjointEigenSolver<MatrixX>(scaled, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
}

/// The largest eigenvalue of M⁻¹A for symmetric Gauss–Seidel, M = (D + L) D⁻¹ (D + U),
/// densely (M⁻¹A is similar to the symmetric L_M⁻¹ A L_M⁻ᵀ, M = L_M L_Mᵀ).
double symmetric_gauss_seidel_lambda_max(Mat A) {
  const MatrixX dense = dense_copy(A);
  const VectorX diagonal = dense.diagonal();
  const MatrixX lower = MatrixX(dense.triangularView<Eigen::Lower>());              // D + L
  const MatrixX factor = lower * diagonal.cwiseSqrt().cwiseInverse().asDiagonal();  // M = factor factorᵀ
  const MatrixX inverse = factor.inverse();
  const MatrixX similar = inverse * dense * inverse.transpose();
  return Eigen::SelfAdjointEigenSolver<MatrixX>(similar, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
}

}  // namespace

TEST(ChebyshevBounds, GershgorinBoundsTheJacobiSpectrumTightlyForFirstOrder) {
  for (const warpfem::CellType type : {warpfem::CellType::triangle, warpfem::CellType::quadrilateral})
    for (const int order : {1, 2}) {
      // A few hundred DOFs each (dense eigenvalues); first order refined, since its top
      // eigenvalue approaches the bound as h → 0 (14–23 % below it here; PETSc's
      // estimate is 3–7 % below it at 10⁶ DOFs).
      warpfem::Mesh<2> mesh = multigrid::test::coarse_l_shape(type, 0.5);
      const int refinements = order == 2 ? 0 : type == warpfem::CellType::triangle ? 2 : 1;
      for (int r = 0; r < refinements; ++r) mesh = warpfem::refine_uniformly(mesh).mesh;
      fem::PoissonProblem<2> p(MPI_COMM_SELF, mesh, std::make_shared<mapping::IdentityMap<2>>(), order,
                               2 * order + 1, multigrid::test::mixed_problem());
      p.assemble();
      const double bound = multigrid::jacobi_gershgorin_bound(p.matrix());
      const double lambda = jacobi_lambda_max(p.matrix());
      std::printf("%s%d, %lld DOFs: Gershgorin %.4f, λmax(D⁻¹A) %.4f\n",
                  type == warpfem::CellType::triangle ? "P" : "Q", order,
                  static_cast<long long>(p.dofs().num_dofs()), bound, lambda);
      EXPECT_GE(bound, lambda * (1 - 1e-12));
      if (order == 1) {
        EXPECT_LE(bound, 1.25 * lambda) << "not tight for a first-order matrix";
      }
    }
}

TEST(ChebyshevBounds, ANonPositiveDiagonalIsAnError) {
  Mat A = nullptr;
  WARPFEM_PETSC_CHECK(MatCreateSeqAIJ(PETSC_COMM_SELF, 2, 2, 2, nullptr, &A));
  WARPFEM_PETSC_CHECK(MatSetValue(A, 0, 0, 2.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(MatSetValue(A, 0, 1, -1.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(MatSetValue(A, 1, 0, -1.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  EXPECT_THROW(multigrid::jacobi_gershgorin_bound(A), Error);
  WARPFEM_PETSC_CHECK(MatDestroy(&A));
}

// Automatic bounds: no eigenvalue estimator on the levels of a P1 solve, PETSc's
// CG estimate for P2; the explicit setting is refused where it is no bound.
TEST(ChebyshevBounds, AutomaticChoiceReachesTheSmoothers) {
  using S = multigrid::MultigridSettings;
  for (const int order : {1, 2}) {
    multigrid::PoissonMultigridSolver<2> mg(
        MPI_COMM_SELF, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 2,
        std::make_shared<mapping::IdentityMap<2>>(), order, 2 * order + 1, multigrid::test::mixed_problem());
    PC pc = nullptr;
    WARPFEM_PETSC_CHECK(KSPGetPC(mg.ksp(), &pc));
    for (PetscInt l = 1; l <= 2; ++l) {
      KSP smoother = nullptr;
      WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, l, &smoother));
      // The fused smoothers find their interval at set-up: Gershgorin's bound for
      // P1, the CG estimate for P2 (PETSc's smoother, chebyshev_kernel petsc, is
      // checked in test_fused_chebyshev.cpp).
      ASSERT_TRUE(multigrid::is_fused_chebyshev_jacobi(smoother)) << "P" << order << ", level " << l;
      const double g = multigrid::jacobi_gershgorin_bound(mg.level(static_cast<int>(l)).matrix());
      const double emax = multigrid::fused_chebyshev_state(smoother).emax;
      if (order == 1) {
        EXPECT_NEAR(emax, g, 1e-12 * g) << "level " << l;
      } else {
        EXPECT_LT(emax, g) << "P2 level " << l << " took Gershgorin's bound";
      }
    }
    const auto report = mg.solve();
    EXPECT_LE(report.linear.iterations, order == 1 ? 12 : 15);
  }
  multigrid::PoissonMultigridOptions o;
  o.multigrid = S{.smoother = S::Smoother::chebyshev_sor, .chebyshev_bounds = S::ChebyshevBounds::gershgorin};
  try {
    multigrid::PoissonMultigridSolver<2> mg(
        MPI_COMM_SELF, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 1,
        std::make_shared<mapping::IdentityMap<2>>(), 1, 3, multigrid::test::mixed_problem(), o);
    ADD_FAILURE() << "Gershgorin bounds with SSOR-preconditioned Chebyshev were accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().key_path, "solver.multigrid.chebyshev_bounds");
  }
}

// -mg_levels_pc_type sor from the options database replaces Jacobi after the
// Gershgorin bounds were set: those levels go back to PETSc's estimate.
TEST(ChebyshevBounds, ASmootherPreconditionerFromTheOptionsGetsTheEstimateBack) {
  multigrid::PoissonMultigridOptions o;
  o.linear.prefix = "cheby_bounds_test_";
  WARPFEM_PETSC_CHECK(PetscOptionsSetValue(nullptr, "-cheby_bounds_test_mg_levels_pc_type", "sor"));
  multigrid::PoissonMultigridSolver<2> mg(
      MPI_COMM_SELF, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 2,
      std::make_shared<mapping::IdentityMap<2>>(), 1, 3, multigrid::test::mixed_problem(), o);
  WARPFEM_PETSC_CHECK(PetscOptionsClearValue(nullptr, "-cheby_bounds_test_mg_levels_pc_type"));
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(mg.ksp(), &pc));
  for (PetscInt l = 1; l <= 2; ++l) {
    KSP smoother = nullptr, estimator = nullptr;
    PC spc = nullptr;
    PCType type = nullptr;
    WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, l, &smoother));
    WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &spc));
    WARPFEM_PETSC_CHECK(PCGetType(spc, &type));
    EXPECT_STREQ(type, PCSOR) << "level " << l;
    WARPFEM_PETSC_CHECK(KSPChebyshevEstEigGetKSP(smoother, &estimator));
    EXPECT_NE(estimator, nullptr) << "level " << l << " kept the Jacobi bound with SOR";
  }
  EXPECT_LE(mg.solve().linear.iterations, 12);
}

// The bound the ssor setting uses holds on warpfem's stiffness matrices and is
// tight (so [0.1, 1.1] is the interval the estimate gave), and automatic bounds
// with Chebyshev–SOR on one process reach the smoothers without an estimator,
// converging as fast as with PETSc's estimate.
TEST(ChebyshevBounds, SymmetricSorBoundsTheSpectrumByOneOnOneProcess) {
  for (const int order : {1, 2}) {
    warpfem::Mesh<2> mesh = multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5);
    if (order == 1) mesh = warpfem::refine_uniformly(mesh).mesh;
    fem::PoissonProblem<2> p(MPI_COMM_SELF, mesh, std::make_shared<mapping::IdentityMap<2>>(), order,
                             2 * order + 1, multigrid::test::mixed_problem());
    p.assemble();
    const double lambda = symmetric_gauss_seidel_lambda_max(p.matrix());
    EXPECT_LE(lambda, 1 + 1e-12) << "P" << order;
    EXPECT_GE(lambda, 0.9) << "P" << order << ": the bound is far from λmax";
  }
  using S = multigrid::MultigridSettings;
  int iterations[2] = {0, 0};
  for (const S::ChebyshevBounds bounds : {S::ChebyshevBounds::automatic, S::ChebyshevBounds::estimate}) {
    multigrid::PoissonMultigridOptions o;
    o.multigrid = S{.smoother = S::Smoother::chebyshev_sor, .chebyshev_bounds = bounds};
    multigrid::PoissonMultigridSolver<2> mg(
        MPI_COMM_SELF, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 3,
        std::make_shared<mapping::IdentityMap<2>>(), 2, 5, multigrid::test::mixed_problem(), o);
    const bool automatic = bounds == S::ChebyshevBounds::automatic;
    EXPECT_EQ(mg.multigrid().settings().chebyshev_bounds, automatic ? S::ChebyshevBounds::ssor : bounds);
    iterations[automatic ? 0 : 1] = mg.solve().linear.iterations;
    PC pc = nullptr;
    WARPFEM_PETSC_CHECK(KSPGetPC(mg.ksp(), &pc));
    for (PetscInt l = 1; l <= 3; ++l) {
      KSP smoother = nullptr, estimator = nullptr;
      WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, l, &smoother));
      WARPFEM_PETSC_CHECK(KSPChebyshevEstEigGetKSP(smoother, &estimator));
      EXPECT_EQ(estimator == nullptr, automatic) << "level " << l;
    }
  }
  EXPECT_LE(iterations[0], iterations[1] + 1);
  EXPECT_LE(iterations[0], 12);
}
