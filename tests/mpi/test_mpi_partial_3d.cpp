// Run under mpiexec -n 2: geometric multigrid for 3D Poisson on a tetrahedral
// or hexahedral hierarchy built for the partition (P1 / Q1: the levels above
// the base stored only around each rank's cells; order 2: whole levels on the
// nested partition) equals the serial solve to solver tolerance, in as many
// CG iterations (± 1).

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

Solved solve(MPI_Comm comm, CellType type, int order, bool partial_levels) {
  multigrid::PoissonMultigridOptions o;
  o.linear.rtol = 1e-10;
  o.partial_levels = partial_levels;
  // 2 ranks: base level 1 (384 tetrahedra or 64 hexahedra), two levels above it.
  o.base_cells_per_part = type == CellType::tetrahedron ? 48 : 24;
  // Order 1: 4913 DOFs; order 2 one level fewer (4913 DOFs, the level above the base whole).
  multigrid::PoissonMultigridSolver<3> mg(comm, unit_cube(2, type), order == 1 ? 3 : 2,
                                          std::make_shared<BentCube>(), order, 2 * order + 1, mixed_problem(),
                                          o);
  Solved r;
  r.iterations = mg.solve().linear.iterations;
  r.u = mg.finest().distribution().gather_all(mg.finest().solution());
  for (const Mesh<3>& level : mg.hierarchy().levels) r.partial_levels += level.partial ? 1 : 0;
  return r;
}

struct Case {
  CellType type;
  int order;
  bool partial_levels;
  std::string name() const {
    return std::string(type == CellType::tetrahedron ? "P" : "Q") + std::to_string(order) +
           (partial_levels ? "_partial" : "_whole");
  }
  // Printed field by field (not as raw bytes, which include the padding).
  friend void PrintTo(const Case& c, std::ostream* os) { *os << c.name(); }
};

class MpiPartialHierarchy3d : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(MpiPartialHierarchy3d, TwoRanksEqualSerial) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const Case c = GetParam();
  const Solved parallel = solve(MPI_COMM_WORLD, c.type, c.order, c.partial_levels);
  const Solved serial = solve(MPI_COMM_SELF, c.type, c.order, c.partial_levels);
  // Partial levels for order 1 when asked for; order 2 (edge DOFs) is always built whole.
  EXPECT_EQ(parallel.partial_levels, c.order == 1 && c.partial_levels ? 2 : 0);
  EXPECT_EQ(serial.partial_levels, 0);
  ASSERT_EQ(parallel.u.size(), serial.u.size());
  EXPECT_LT((parallel.u - serial.u).lpNorm<Eigen::Infinity>(), 1e-8 * serial.u.lpNorm<Eigen::Infinity>());
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("[ iterations ] %s: %d on 2 ranks, %d serial\n", c.name().c_str(), parallel.iterations,
                serial.iterations);
  EXPECT_LE(std::abs(parallel.iterations - serial.iterations), 1)
      << "parallel " << parallel.iterations << ", serial " << serial.iterations;
}

INSTANTIATE_TEST_SUITE_P(
    Cells, MpiPartialHierarchy3d,
    ::testing::Values(Case{CellType::tetrahedron, 1, true}, Case{CellType::tetrahedron, 1, false},
                      Case{CellType::tetrahedron, 2, true}, Case{CellType::hexahedron, 1, true},
                      Case{CellType::hexahedron, 1, false}, Case{CellType::hexahedron, 2, true}),
    [](const auto& info) { return info.param.name(); });
