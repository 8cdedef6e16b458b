// The fused Chebyshev–Jacobi smoother runs PETSc's Chebyshev–Jacobi iteration:
// the same iterates from zero and nonzero initial guesses, on one rank and
// (built again as test_mpi_fused_chebyshev) on two, where the off-rank
// columns go through the ghost gather. In single precision it differs only
// by float rounding of the matrix values. It is what P1 multigrid levels run
// by default, with the iteration counts of PETSc's smoother.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstring>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/handles.hpp"
#include "core/petsc/scatter.hpp"
#include "mapping/make_map.hpp"
#include "multigrid/chebyshev_bounds.hpp"
#include "multigrid/fused_chebyshev_jacobi.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "multigrid_fixtures.hpp"

using namespace warpfem;

namespace {

mapping::MapPtr<2> bent_pentagon_map() {
  mapping::MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}}, "pentagon");
  spec.target = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 0.75}, {0, 1}}, "bent pentagon");
  return mapping::make_map(spec);
}

/// A warped P1 stiffness matrix (variable coefficients, Dirichlet rows) on `comm`.
std::unique_ptr<fem::PoissonProblem<2>> warped_problem(MPI_Comm comm) {
  const mapping::MapPtr<2> map = bent_pentagon_map();
  const Polygon pentagon = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}}, "pentagon");
  const warpfem::Mesh<2> mesh =
      warpfem::refine_uniformly(warpfem::structured_mesh(pentagon, 8, 8, warpfem::CellType::triangle)).mesh;
  auto p = std::make_unique<fem::PoissonProblem<2>>(comm, mesh, map, 1, 4,
                                                    multigrid::test::mixed_problem(pentagon));
  p->assemble();
  return p;
}

petsc::LinearSolver smoother_ksp(Mat A, int steps, bool zero_guess) {
  MPI_Comm comm = MPI_COMM_NULL;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  petsc::LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(comm, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), A, A));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp.get(), 0.0, 0.0, PETSC_DEFAULT, steps));
  WARPFEM_PETSC_CHECK(KSPSetNormType(ksp.get(), KSP_NORM_NONE));
  WARPFEM_PETSC_CHECK(KSPSetConvergenceTest(ksp.get(), KSPConvergedSkip, nullptr, nullptr));
  WARPFEM_PETSC_CHECK(KSPSetInitialGuessNonzero(ksp.get(), zero_guess ? PETSC_FALSE : PETSC_TRUE));
  return ksp;
}

/// x after `steps` smoothing steps on A x = b from x0 (or zero), on every rank.
VectorX smooth(KSP ksp, Vec b, Vec x0) {
  petsc::Vector x;
  WARPFEM_PETSC_CHECK(VecDuplicate(x0, x.out()));
  WARPFEM_PETSC_CHECK(VecCopy(x0, x.get()));
  WARPFEM_PETSC_CHECK(KSPSolve(ksp, b, x.get()));
  const std::vector<PetscScalar> all = petsc::gather_to_all(x.get());
  return Eigen::Map<const VectorX>(all.data(), static_cast<Index>(all.size()));
}

petsc::Vector random_vector(Vec like, unsigned seed) {
  petsc::Vector v;
  WARPFEM_PETSC_CHECK(VecDuplicate(like, v.out()));
  PetscRandom rnd = nullptr;
  WARPFEM_PETSC_CHECK(PetscRandomCreate(PETSC_COMM_WORLD, &rnd));
  WARPFEM_PETSC_CHECK(PetscRandomSetSeed(rnd, seed));
  WARPFEM_PETSC_CHECK(PetscRandomSeed(rnd));
  WARPFEM_PETSC_CHECK(VecSetRandom(v.get(), rnd));
  WARPFEM_PETSC_CHECK(PetscRandomDestroy(&rnd));
  return v;
}

}  // namespace

/// 1D Laplacian (2, −1) with rows and columns in a random order, n rows split
/// over the ranks: on two ranks about half of every row's couplings are off-rank.
petsc::Matrix permuted_laplacian(PetscInt n) {
  std::vector<PetscInt> position(static_cast<std::size_t>(n));
  std::iota(position.begin(), position.end(), 0);
  std::shuffle(position.begin(), position.end(), std::mt19937(11));
  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(
      MatCreateAIJ(PETSC_COMM_WORLD, PETSC_DECIDE, PETSC_DECIDE, n, n, 3, nullptr, 2, nullptr, A.out()));
  PetscInt begin = 0, end = 0;
  WARPFEM_PETSC_CHECK(MatGetOwnershipRange(A.get(), &begin, &end));
  for (PetscInt node = 0; node < n; ++node) {
    const PetscInt row = position[static_cast<std::size_t>(node)];
    if (row < begin || row >= end) continue;
    WARPFEM_PETSC_CHECK(MatSetValue(A.get(), row, row, 2.0, INSERT_VALUES));
    if (node > 0) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), row, position[node - 1], -1.0, INSERT_VALUES));
    if (node + 1 < n) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), row, position[node + 1], -1.0, INSERT_VALUES));
  }
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A.get(), MAT_FINAL_ASSEMBLY));
  return A;
}

/// Fused smoothing (double and single precision) against KSPCHEBYSHEV + PCJACOBI on [0.1, 1]·g.
void expect_petscs_iteration(Mat A) {
  const double g = multigrid::jacobi_gershgorin_bound(A);
  petsc::Vector like;
  WARPFEM_PETSC_CHECK(MatCreateVecs(A, like.out(), nullptr));
  const petsc::Vector b = random_vector(like.get(), 3), x0 = random_vector(like.get(), 7);
  for (const bool zero_guess : {true, false})
    for (const int steps : {1, 2, 3}) {
      SCOPED_TRACE("steps " + std::to_string(steps) + (zero_guess ? ", zero guess" : ", nonzero guess"));
      petsc::LinearSolver reference = smoother_ksp(A, steps, zero_guess);
      WARPFEM_PETSC_CHECK(KSPSetType(reference.get(), KSPCHEBYSHEV));
      WARPFEM_PETSC_CHECK(KSPChebyshevEstEigSet(reference.get(), 0.0, 0.0, 0.0, 0.0));
      WARPFEM_PETSC_CHECK(KSPChebyshevSetEigenvalues(reference.get(), g, 0.1 * g));
      PC pc = nullptr;
      WARPFEM_PETSC_CHECK(KSPGetPC(reference.get(), &pc));
      WARPFEM_PETSC_CHECK(PCSetType(pc, PCJACOBI));
      const VectorX expected = smooth(reference.get(), b.get(), x0.get());
      const std::vector<PetscScalar> x0_all = petsc::gather_to_all(x0.get());
      const VectorX start = zero_guess ? VectorX::Zero(expected.size())
                                       : VectorX(Eigen::Map<const VectorX>(x0_all.data(), expected.size()));
      // The smoother moved the iterate, so the comparison below is not trivial.
      EXPECT_GT((expected - start).norm(), 1e-2 * expected.norm());

      for (const auto precision :
           {multigrid::SmootherPrecision::double_precision, multigrid::SmootherPrecision::single}) {
        const bool single = precision == multigrid::SmootherPrecision::single;
        petsc::LinearSolver fused = smoother_ksp(A, steps, zero_guess);
        multigrid::set_fused_chebyshev_jacobi(fused.get(),
                                              {.lower = 0.1, .upper = 1.0, .precision = precision});
        const VectorX got = smooth(fused.get(), b.get(), x0.get());
        EXPECT_TRUE(multigrid::is_fused_chebyshev_jacobi(fused.get()));
        const auto state = multigrid::fused_chebyshev_state(fused.get());
        EXPECT_NEAR(state.emax, g, 1e-12 * g);
        EXPECT_NEAR(state.emin, 0.1 * g, 1e-12 * g);
        EXPECT_EQ(state.single_precision, single);
        const double diff = (got - expected).lpNorm<Eigen::Infinity>();
        EXPECT_LE(diff, (single ? 1e-6 : 1e-13) * expected.lpNorm<Eigen::Infinity>())
            << (single ? "single" : "double") << " precision, max difference " << diff;
      }
    }
}

/// Two 1D Laplacians (2, −1) of n/2 rows each, side by side and not coupled:
/// on two ranks each rank owns one of them, so no rank has a ghost column.
petsc::Matrix two_chains(PetscInt n) {
  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(
      MatCreateAIJ(PETSC_COMM_WORLD, PETSC_DECIDE, PETSC_DECIDE, n, n, 3, nullptr, 2, nullptr, A.out()));
  PetscInt begin = 0, end = 0;
  WARPFEM_PETSC_CHECK(MatGetOwnershipRange(A.get(), &begin, &end));
  const PetscInt half = n / 2;
  for (PetscInt row = begin; row < end; ++row) {
    const PetscInt first = row < half ? 0 : half, last = row < half ? half : n;
    WARPFEM_PETSC_CHECK(MatSetValue(A.get(), row, row, 2.0, INSERT_VALUES));
    if (row > first) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), row, row - 1, -1.0, INSERT_VALUES));
    if (row + 1 < last) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), row, row + 1, -1.0, INSERT_VALUES));
  }
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A.get(), MAT_FINAL_ASSEMBLY));
  return A;
}

TEST(FusedChebyshev, RunsPetscsChebyshevJacobiIteration) {
  const auto p = warped_problem(MPI_COMM_WORLD);
  expect_petscs_iteration(p->matrix());
  // No locality at all: scattered columns, and on two ranks many ghost columns.
  const petsc::Matrix A = permuted_laplacian(20000);
  expect_petscs_iteration(A.get());
  // On two ranks: an off-diagonal block without columns, so nothing to gather.
  const petsc::Matrix B = two_chains(2000);
  expect_petscs_iteration(B.get());
}

/// References to `A` held by a smoother on it after one smoothing step.
PetscInt references_while_smoothing(Mat A, bool fused) {
  petsc::LinearSolver smoother = smoother_ksp(A, 2, false);
  if (fused) {
    multigrid::set_fused_chebyshev_jacobi(smoother.get());
  } else {
    WARPFEM_PETSC_CHECK(KSPSetType(smoother.get(), KSPCHEBYSHEV));
    WARPFEM_PETSC_CHECK(KSPChebyshevEstEigSet(smoother.get(), 0.0, 0.0, 0.0, 0.0));
    WARPFEM_PETSC_CHECK(KSPChebyshevSetEigenvalues(smoother.get(), 2.0, 0.2));
    PC pc = nullptr;
    WARPFEM_PETSC_CHECK(KSPGetPC(smoother.get(), &pc));
    WARPFEM_PETSC_CHECK(PCSetType(pc, PCJACOBI));
  }
  petsc::Vector b, x;
  WARPFEM_PETSC_CHECK(MatCreateVecs(A, x.out(), b.out()));
  WARPFEM_PETSC_CHECK(VecSet(b.get(), 1.0));
  WARPFEM_PETSC_CHECK(VecSet(x.get(), 0.0));
  WARPFEM_PETSC_CHECK(KSPSolve(smoother.get(), b.get(), x.get()));
  PetscInt count = 0;
  WARPFEM_PETSC_CHECK(PetscObjectGetReference(reinterpret_cast<PetscObject>(A), &count));
  return count;
}

// The fused smoother reads the rows of a sequential level matrix from set-up
// on, so it holds a reference of its own (PCDestroy drops the PC's references
// before the shell's destroy callback restores the rows), and gives it back.
TEST(FusedChebyshev, HoldsItsMatrixWhileItReadsItsRows) {
  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(MatCreateSeqAIJ(PETSC_COMM_SELF, 3, 3, 3, nullptr, A.out()));
  for (PetscInt r = 0; r < 3; ++r) {
    WARPFEM_PETSC_CHECK(MatSetValue(A.get(), r, r, 2.0, INSERT_VALUES));
    if (r > 0) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), r, r - 1, -1.0, INSERT_VALUES));
    if (r < 2) WARPFEM_PETSC_CHECK(MatSetValue(A.get(), r, r + 1, -1.0, INSERT_VALUES));
  }
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A.get(), MAT_FINAL_ASSEMBLY));
  PetscInt before = 0, after = 0;
  WARPFEM_PETSC_CHECK(PetscObjectGetReference(reinterpret_cast<PetscObject>(A.get()), &before));
  EXPECT_EQ(references_while_smoothing(A.get(), true), references_while_smoothing(A.get(), false) + 1);
  WARPFEM_PETSC_CHECK(PetscObjectGetReference(reinterpret_cast<PetscObject>(A.get()), &after));
  EXPECT_EQ(after, before) << "a reference is left behind";

  // The caller lets go of the matrix before the smoother: nothing reads freed rows
  // (run under valgrind to see it).
  petsc::LinearSolver smoother = smoother_ksp(A.get(), 2, false);
  multigrid::set_fused_chebyshev_jacobi(smoother.get());
  WARPFEM_PETSC_CHECK(KSPSetUp(smoother.get()));
  A.reset();
}

// New values in the level matrices (a re-assembly) reach the fused smoothers
// and residuals at the next solve: with every level scaled by 2 the same
// iterations give half the solution.
TEST(FusedChebyshev, NewMatrixValuesReachTheSmoothers) {
  multigrid::PoissonMultigridOptions o;
  o.linear.rtol = 1e-10;
  multigrid::PoissonMultigridSolver<2> mg(
      PETSC_COMM_WORLD, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 3,
      std::make_shared<mapping::IdentityMap<2>>(), 1, 3, multigrid::test::mixed_problem(), o);
  petsc::Vector start;
  WARPFEM_PETSC_CHECK(VecDuplicate(mg.finest().solution(), start.out()));
  WARPFEM_PETSC_CHECK(VecCopy(mg.finest().solution(), start.get()));
  const auto first = mg.solve();
  const VectorX u = mg.finest().distribution().gather_all(mg.finest().solution());
  for (int l = 0; l < mg.hierarchy().num_levels(); ++l)
    WARPFEM_PETSC_CHECK(MatScale(mg.level(l).matrix(), 2.0));
  WARPFEM_PETSC_CHECK(VecCopy(start.get(), mg.finest().solution()));
  const auto second = mg.solve();
  const VectorX half = mg.finest().distribution().gather_all(mg.finest().solution());
  EXPECT_EQ(second.linear.iterations, first.linear.iterations);
  EXPECT_LE((2.0 * half - u).lpNorm<Eigen::Infinity>(), 1e-8 * u.lpNorm<Eigen::Infinity>());
}

TEST(FusedChebyshev, RefusesBadIntervalsAndNonPositiveDiagonals) {
  petsc::LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_WORLD, ksp.out()));
  EXPECT_THROW(multigrid::set_fused_chebyshev_jacobi(ksp.get(), {.lower = 0.0, .upper = 1.0}), Error);
  EXPECT_THROW(multigrid::set_fused_chebyshev_jacobi(ksp.get(), {.lower = 0.5, .upper = 0.5}), Error);

  // Every rank owns one row; the last row has a zero diagonal entry.
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  petsc::Matrix A;
  WARPFEM_PETSC_CHECK(MatCreateAIJ(PETSC_COMM_WORLD, 2, 2, PETSC_DETERMINE, PETSC_DETERMINE, 2, nullptr, 1,
                                   nullptr, A.out()));
  const PetscInt first = 2 * rank, n = 2 * size;
  WARPFEM_PETSC_CHECK(MatSetValue(A.get(), first, first, 2.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(MatSetValue(A.get(), first, first + 1, -1.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(MatSetValue(A.get(), first + 1, first, -1.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(
      MatSetValue(A.get(), first + 1, first + 1, first + 1 == n - 1 ? 0.0 : 2.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(MatAssemblyBegin(A.get(), MAT_FINAL_ASSEMBLY));
  WARPFEM_PETSC_CHECK(MatAssemblyEnd(A.get(), MAT_FINAL_ASSEMBLY));
  // Every rank fails (the checks are reduced over the communicator), none waits:
  // PETSc's kernel takes Gershgorin's bound from jacobi_gershgorin_bound, ...
  EXPECT_THROW(multigrid::jacobi_gershgorin_bound(A.get()), Error);
  // ... the fused smoother finds it in its own set-up.
  petsc::LinearSolver smoother = smoother_ksp(A.get(), 2, true);
  multigrid::set_fused_chebyshev_jacobi(smoother.get());
  try {
    WARPFEM_PETSC_CHECK(KSPSetUp(smoother.get()));
    ADD_FAILURE() << "a zero diagonal entry was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("positive diagonal"), std::string::npos) << e.what();
  }
}

// The CG estimate of λmax(D⁻¹A) (P2/Q2 levels) is a Ritz value: at most λmax,
// and close to it after 10 steps.
TEST(FusedChebyshev, CgEstimateApproachesTheJacobiSpectrumFromBelow) {
  fem::PoissonProblem<2> p(
      PETSC_COMM_WORLD, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5),
      std::make_shared<mapping::IdentityMap<2>>(), 2, 6, multigrid::test::mixed_problem());
  p.assemble();
  // λmax(D^{-1/2} A D^{-1/2}) densely, from the whole matrix on every rank.
  const PetscInt n = p.distribution().num_global();
  Mat* whole = nullptr;
  IS all = nullptr;
  WARPFEM_PETSC_CHECK(ISCreateStride(PETSC_COMM_SELF, n, 0, 1, &all));
  WARPFEM_PETSC_CHECK(MatCreateSubMatrices(p.matrix(), 1, &all, &all, MAT_INITIAL_MATRIX, &whole));
  MatrixX dense = MatrixX::Zero(n, n);
  for (PetscInt r = 0; r < n; ++r) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    WARPFEM_PETSC_CHECK(MatGetRow(whole[0], r, &nz, &cols, &vals));
    for (PetscInt k = 0; k < nz; ++k) dense(r, cols[k]) = vals[k];
    WARPFEM_PETSC_CHECK(MatRestoreRow(whole[0], r, &nz, &cols, &vals));
  }
  WARPFEM_PETSC_CHECK(MatDestroySubMatrices(1, &whole));
  WARPFEM_PETSC_CHECK(ISDestroy(&all));
  const VectorX scale = dense.diagonal().cwiseSqrt().cwiseInverse();
  const MatrixX scaled = scale.asDiagonal() * dense * scale.asDiagonal();
  const double lambda =
      Eigen::SelfAdjointEigenSolver<MatrixX>(scaled, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();

  petsc::LinearSolver smoother = smoother_ksp(p.matrix(), 2, true);
  multigrid::set_fused_chebyshev_jacobi(
      smoother.get(), {.lower = 0.1, .upper = 1.1, .bound = multigrid::ChebyshevBound::cg_estimate});
  WARPFEM_PETSC_CHECK(KSPSetUp(smoother.get()));
  const auto state = multigrid::fused_chebyshev_state(smoother.get());
  const double estimate = state.emax / 1.1;
  EXPECT_LE(estimate, lambda * (1 + 1e-10));
  EXPECT_GE(estimate, 0.9 * lambda);
  EXPECT_NEAR(state.emin, 0.1 * estimate, 1e-12 * estimate);
  // Gershgorin's bound overshoots for P2, which is why these levels estimate.
  EXPECT_GT(multigrid::jacobi_gershgorin_bound(p.matrix()), 1.2 * lambda);
}

// Chebyshev–Jacobi levels are fused by default (P1 with Gershgorin's bound, P2
// with the CG estimate) and take the iterations of PETSc's smoother; the options
// database can still replace the smoother.
TEST(FusedChebyshev, MultigridLevelsAreFusedWithPetscsIterations) {
  using Kernel = multigrid::MultigridSettings::ChebyshevKernel;
  for (const int order : {1, 2}) {
    const int refinements = order == 1 ? 3 : 2;
    VectorX reference;
    int reference_iterations = 0;
    for (const Kernel kernel : {Kernel::petsc, Kernel::fused_double, Kernel::fused_single}) {
      SCOPED_TRACE("P" + std::to_string(order) + ", kernel " + std::to_string(static_cast<int>(kernel)));
      multigrid::PoissonMultigridOptions o;
      o.multigrid.chebyshev_kernel = kernel;
      o.linear.rtol = 1e-10;
      multigrid::PoissonMultigridSolver<2> mg(
          PETSC_COMM_WORLD, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), refinements,
          std::make_shared<mapping::IdentityMap<2>>(), order, 2 * order + 1, multigrid::test::mixed_problem(),
          o);
      PC pc = nullptr;
      WARPFEM_PETSC_CHECK(KSPGetPC(mg.ksp(), &pc));
      for (PetscInt l = 1; l <= refinements; ++l) {
        KSP smoother = nullptr;
        WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, l, &smoother));
        EXPECT_EQ(multigrid::is_fused_chebyshev_jacobi(smoother), kernel != Kernel::petsc) << "level " << l;
      }
      const auto report = mg.solve();
      const VectorX u = mg.finest().distribution().gather_all(mg.finest().solution());
      if (kernel == Kernel::petsc) {
        reference = u;
        reference_iterations = report.linear.iterations;
        EXPECT_LE(reference_iterations, 16);
        continue;
      }
      // P1: the same interval, so the same iterations. P2: PETSc estimates λmax from
      // its own random right-hand side, so the intervals differ by a few per cent.
      if (order == 1) {
        EXPECT_EQ(report.linear.iterations, reference_iterations);
      } else {
        EXPECT_LE(std::abs(report.linear.iterations - reference_iterations), 1);
      }
      EXPECT_LE((u - reference).lpNorm<Eigen::Infinity>(), 1e-8 * reference.lpNorm<Eigen::Infinity>());
    }
  }

  // Levels whose smoother the options name or monitor keep PETSc's (PCMG reads
  // the options again at set-up, and a monitor wants every step).
  const std::pair<const char*, const char*> options[] = {
      {"-fused_option_test_mg_levels_ksp_monitor", "ascii:/dev/null"},
      {"-fused_option_test_mg_levels_ksp_type", "chebyshev"},
      {"-fused_option_test_mg_levels_pc_type", "jacobi"}};
  for (const auto& [name, value] : options) {
    SCOPED_TRACE(name);
    multigrid::PoissonMultigridOptions o;
    o.linear.prefix = "fused_option_test_";
    WARPFEM_PETSC_CHECK(PetscOptionsSetValue(nullptr, name, value));
    multigrid::PoissonMultigridSolver<2> mg(
        PETSC_COMM_WORLD, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 1,
        std::make_shared<mapping::IdentityMap<2>>(), 1, 3, multigrid::test::mixed_problem(), o);
    WARPFEM_PETSC_CHECK(PetscOptionsClearValue(nullptr, name));
    PC pc = nullptr;
    KSP smoother = nullptr;
    WARPFEM_PETSC_CHECK(KSPGetPC(mg.ksp(), &pc));
    WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, 1, &smoother));
    EXPECT_FALSE(multigrid::is_fused_chebyshev_jacobi(smoother));
    EXPECT_LE(mg.solve().linear.iterations, 12);
  }
}
