// Run under mpiexec -n 2: geometric multigrid for 3D Poisson on a tetrahedral
// hierarchy built for the partition (P1: the levels above the base stored only
// around each rank's cells; P2: whole levels on the nested partition) equals
// the serial solve to solver tolerance, in as many CG iterations (± 1).

#include <gtest/gtest.h>

#include <cstdio>
#include <ostream>
#include <string>

#include "multigrid/poisson_multigrid.hpp"
#include "tests/fem/poisson_3d_fixtures.hpp"

using namespace warpfem;
using namespace warpfem::testing3d;

namespace {

struct Solved {
  VectorX u;  ///< at every mesh DOF
  int iterations = 0;
  int partial_levels = 0;
};

Solved solve(MPI_Comm comm, int order, bool partial_levels) {
  multigrid::PoissonMultigridOptions o;
  o.linear.rtol = 1e-10;
  o.partial_levels = partial_levels;
  o.base_cells_per_part = 48;  // 2 ranks: base level 1 of 384 cells, two levels above it
  // P1: 4913 DOFs; P2 one level fewer (4913 DOFs, the level above the base whole).
  multigrid::PoissonMultigridSolver<3> mg(comm, unit_cube(2, CellType::tetrahedron), order == 1 ? 3 : 2,
                                          std::make_shared<BentCube>(), order, 2 * order + 1, mixed_problem(),
                                          o);
  Solved r;
  r.iterations = mg.solve().linear.iterations;
  r.u = mg.finest().distribution().gather_all(mg.finest().solution());
  for (const Mesh<3>& level : mg.hierarchy().levels) r.partial_levels += level.partial ? 1 : 0;
  return r;
}

struct Case {
  int order;
  bool partial_levels;
  // Printed field by field (not as raw bytes, which include the padding).
  friend void PrintTo(const Case& c, std::ostream* os) {
    *os << "P" << c.order << (c.partial_levels ? " partial" : " whole");
  }
};

class MpiPartialHierarchy3d : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(MpiPartialHierarchy3d, TwoRanksEqualSerial) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const Case c = GetParam();
  const Solved parallel = solve(MPI_COMM_WORLD, c.order, c.partial_levels);
  const Solved serial = solve(MPI_COMM_SELF, c.order, c.partial_levels);
  // Partial levels for P1 when asked for; P2 (edge DOFs) is always built whole.
  EXPECT_EQ(parallel.partial_levels, c.order == 1 && c.partial_levels ? 2 : 0);
  EXPECT_EQ(serial.partial_levels, 0);
  ASSERT_EQ(parallel.u.size(), serial.u.size());
  EXPECT_LT((parallel.u - serial.u).lpNorm<Eigen::Infinity>(), 1e-8 * serial.u.lpNorm<Eigen::Infinity>());
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("[ iterations ] P%d: %d on 2 ranks, %d serial\n", c.order, parallel.iterations,
                serial.iterations);
  EXPECT_LE(std::abs(parallel.iterations - serial.iterations), 1)
      << "parallel " << parallel.iterations << ", serial " << serial.iterations;
}

INSTANTIATE_TEST_SUITE_P(Tetrahedra, MpiPartialHierarchy3d,
                         ::testing::Values(Case{1, true}, Case{1, false}, Case{2, true}),
                         [](const auto& info) {
                           return "P" + std::to_string(info.param.order) +
                                  (info.param.partial_levels ? "_partial" : "_whole");
                         });
