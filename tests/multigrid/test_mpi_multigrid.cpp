// Run under mpiexec -n 2: the distributed multigrid solve equals the serial one.

#include <gtest/gtest.h>

#include "elasticity_multigrid_fixtures.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "multigrid_fixtures.hpp"

using namespace warpfem;

namespace {
struct Result {
  VectorX u;
  int iterations;
};

Result run(MPI_Comm comm, int order) {
  multigrid::PoissonMultigridOptions o;
  o.linear.rtol = 1e-11;
  multigrid::PoissonMultigridSolver mg(comm, multigrid::test::coarse_l_shape(fem::CellType::triangle, 0.5), 3,
                                       std::make_shared<mapping::IdentityMap<2>>(), order, 2 * order + 1,
                                       multigrid::test::mixed_problem(), o);
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
}

INSTANTIATE_TEST_SUITE_P(Orders, MpiMultigrid, ::testing::Values(1, 2));

TEST(MpiElasticityMultigrid, TwoRankSolveMatchesTheDirectSolver) {
  // The vector prolongations across rank boundaries: GMRES + multigrid on 2 ranks
  // reproduces the parallel LU solution, in as many iterations as in serial (±3).
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  for (int order : {1, 2}) {
    const auto r = multigrid::test::solve_both(fem::CellType::triangle, order, 2);
    EXPECT_LT(r.relative_difference, 1e-7) << "P" << order;
    EXPECT_LE(r.iterations, 30) << "P" << order;
  }
}
