// Run under mpiexec -n 2: the distributed multigrid solve equals the serial one.

#include <gtest/gtest.h>

#include <memory>
#include <set>

#include "elasticity_multigrid_fixtures.hpp"
#include "multigrid/chebyshev_bounds.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "multigrid_fixtures.hpp"

using namespace warpfem;

namespace {
struct Result {
  VectorX u;
  int iterations;
};

Result run(MPI_Comm comm, int order, multigrid::MultigridSettings settings = {}) {
  multigrid::PoissonMultigridOptions o;
  o.multigrid = settings;
  o.linear.rtol = 1e-11;
  multigrid::PoissonMultigridSolver<2> mg(
      comm, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 3,
      std::make_shared<mapping::IdentityMap<2>>(), order, 2 * order + 1, multigrid::test::mixed_problem(), o);
  const auto report = mg.solve();
  return {mg.finest().distribution().gather_all(mg.finest().solution()), report.linear.iterations};
}
}  // namespace

class MpiMultigrid : public ::testing::TestWithParam<int> {};

TEST_P(MpiMultigrid, TwoRanksEqualSerial) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const Result parallel = run(MPI_COMM_WORLD, GetParam());
  const Result serial = run(MPI_COMM_SELF, GetParam());
  ASSERT_EQ(parallel.u.size(), serial.u.size());
  const double diff = (parallel.u - serial.u).lpNorm<Eigen::Infinity>();
  EXPECT_LT(diff, 1e-8 * serial.u.lpNorm<Eigen::Infinity>()) << "max difference " << diff;
  EXPECT_LE(std::abs(parallel.iterations - serial.iterations), 3);
  // P1: Chebyshev–Jacobi with Gershgorin bounds does not depend on the partition
  // (no random eigenvalue estimate, no processor blocks), so neither does CG.
  if (GetParam() == 1) {
    EXPECT_EQ(parallel.iterations, serial.iterations);
  }
}

// Smoothed prolongations with their Galerkin operators (PETSc's parallel
// products) give the serial solution too.
TEST_P(MpiMultigrid, SmoothedProlongationTwoRanksEqualSerial) {
  const multigrid::MultigridSettings smoothed{.prolongation =
                                                  multigrid::MultigridSettings::Prolongation::smoothed};
  const Result parallel = run(MPI_COMM_WORLD, GetParam(), smoothed);
  const Result serial = run(MPI_COMM_SELF, GetParam(), smoothed);
  ASSERT_EQ(parallel.u.size(), serial.u.size());
  const double diff = (parallel.u - serial.u).lpNorm<Eigen::Infinity>();
  EXPECT_LT(diff, 1e-8 * serial.u.lpNorm<Eigen::Infinity>()) << "max difference " << diff;
  EXPECT_LE(std::abs(parallel.iterations - serial.iterations), 3);
}

INSTANTIATE_TEST_SUITE_P(Orders, MpiMultigrid, ::testing::Values(1, 2));

TEST(MpiMultigrid, FineLevelsAreDistributedInsideTheirParentsRanks) {
  // Five refinements: the levels beyond the first with >= kBaseCellsPerPart cells per rank
  // inherit their parents' owners, so each rank's fine cells lie in its coarse cells.
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const auto solver = [](MPI_Comm comm) {
    multigrid::PoissonMultigridOptions o;
    o.linear.rtol = 1e-11;
    return std::make_unique<multigrid::PoissonMultigridSolver<2>>(
        comm, multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 5,
        std::make_shared<mapping::IdentityMap<2>>(), 1, 3, multigrid::test::mixed_problem(), o);
  };
  const auto mg = solver(MPI_COMM_WORLD);
  const fem::MeshHierarchy<2>& h = mg->hierarchy();
  int nested_levels = 0;
  for (int l = 1; l < h.num_levels(); ++l) {
    if (h.levels[static_cast<std::size_t>(l - 1)].num_cells() < fem::kBaseCellsPerPart * size)
      continue;  // not yet inherited
    ++nested_levels;
    const auto& coarse_cells = mg->level(l - 1).distribution().local_cells();
    const std::set<Index> coarse(coarse_cells.begin(), coarse_cells.end());
    const auto& fine_cells = mg->level(l).distribution().local_cells();
    EXPECT_EQ(fine_cells.size(), 4 * coarse_cells.size()) << "level " << l;
    for (const Index c : fine_cells)
      ASSERT_TRUE(coarse.count(warpfem::RefinedMesh<2>::parent_of(c))) << "level " << l << ", cell " << c;
  }
  EXPECT_GE(nested_levels, 2);
  // The Chebyshev bound is global: the same on two ranks as on one.
  const auto serial_mg = solver(MPI_COMM_SELF);
  EXPECT_DOUBLE_EQ(multigrid::jacobi_gershgorin_bound(mg->finest().matrix()),
                   multigrid::jacobi_gershgorin_bound(serial_mg->finest().matrix()));
  const VectorX parallel = (mg->solve(), mg->finest().distribution().gather_all(mg->finest().solution()));
  serial_mg->solve();
  const VectorX serial = serial_mg->finest().distribution().gather_all(serial_mg->finest().solution());
  EXPECT_LT((parallel - serial).lpNorm<Eigen::Infinity>(), 1e-8 * serial.lpNorm<Eigen::Infinity>());
}

TEST(MpiElasticityMultigrid, TwoRankSolveMatchesTheDirectSolver) {
  // The vector prolongations across rank boundaries: GMRES + multigrid on 2 ranks
  // reproduces the parallel LU solution, in as many iterations as in serial (±3).
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  for (int order : {1, 2}) {
    const auto r = multigrid::test::solve_both(warpfem::CellType::triangle, order, 2);
    EXPECT_LT(r.relative_difference, 1e-7) << "P" << order;
    EXPECT_LE(r.iterations, 30) << "P" << order;
  }
}

TEST(MpiElasticityMultigrid, CoarseLevelsAreNestedUnderAFinestSpaceOnTheNestedPartition) {
  // An operator built on nested_partitions(...).back() (as the elasticity app does
  // with pc_type "mg"): every inherited level's local cells lie in the local cells
  // of the level below, up to the finest space.
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  // An unstructured coarse mesh: per-level Morton cuts of its refinements are not
  // nested (those of a structured square would be).
  const fem::MeshHierarchy<2> hierarchy(multigrid::test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 5);
  const std::vector<std::vector<int>> owners = fem::nested_partitions(hierarchy, size);
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, hierarchy.finest(),
                                     std::make_shared<mapping::IdentityMap<2>>(), 1, 0,
                                     multigrid::test::clamped_block(), owners.back());
  const multigrid::GeometricMultigrid mg(hierarchy, op);
  const auto local_cells = [&](int l) -> const std::vector<Index>& {
    return l + 1 == mg.num_levels() ? op.space().nodes().local_cells()
                                    : mg.coarse_distribution(l).local_cells();
  };
  int nested_levels = 0;
  for (int l = 1; l < mg.num_levels(); ++l) {
    if (hierarchy.levels[static_cast<std::size_t>(l - 1)].num_cells() < fem::kBaseCellsPerPart * size)
      continue;  // not inherited
    ++nested_levels;
    const std::set<Index> coarse(local_cells(l - 1).begin(), local_cells(l - 1).end());
    EXPECT_EQ(local_cells(l).size(), 4 * coarse.size()) << "level " << l;
    for (const Index c : local_cells(l))
      ASSERT_TRUE(coarse.count(warpfem::RefinedMesh<2>::parent_of(c))) << "level " << l << ", cell " << c;
  }
  EXPECT_GE(nested_levels, 2);
  EXPECT_THROW(mg.coarse_distribution(mg.num_levels() - 1), Error);
}
