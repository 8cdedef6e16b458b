// Run under mpiexec -n 2: 3D Poisson (Dirichlet and Neumann parts by facet
// tag, warped cube) and its geometric multigrid solve on two ranks equal the
// serial ones.

#include <gtest/gtest.h>

#include "core/petsc/check.hpp"
#include "fem/physics/poisson.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "tests/fem/poisson_3d_fixtures.hpp"

using namespace warpfem;
using namespace warpfem::testing3d;

namespace {

struct Solved {
  VectorX u;  ///< at every mesh DOF
  double area = 0, l2 = 0;
};

Solved solve(MPI_Comm comm, const Mesh<3>& mesh, int order) {
  fem::PoissonProblem<3> p(comm, mesh, std::make_shared<BentCube>(), order, 2 * order + 2, mixed_problem());
  p.assemble();
  p.solve({.ksp_type = "cg",
           .pc_type = "jacobi",
           .rtol = 1e-13,
           .atol = 1e-50,
           .max_iterations = 5000,
           .prefix = "",
           .direct_below = 0});
  const auto e = p.errors([](const Point<3>& x, double) { return smooth_u(x); },
                          [](const Point<3>& x, double) { return smooth_grad(x); });
  return {p.distribution().gather_all(p.solution()), p.area(), e.l2};
}

struct Case {
  CellType type;
  int order, n;
};

class MpiPoisson3d : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(MpiPoisson3d, TwoRanksEqualSerial) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const Case c = GetParam();
  const Mesh<3> mesh = unit_cube(c.n, c.type);
  const Solved parallel = solve(MPI_COMM_WORLD, mesh, c.order), serial = solve(MPI_COMM_SELF, mesh, c.order);
  ASSERT_EQ(parallel.u.size(), serial.u.size());
  EXPECT_LT((parallel.u - serial.u).lpNorm<Eigen::Infinity>(), 1e-9 * serial.u.lpNorm<Eigen::Infinity>());
  EXPECT_NEAR(parallel.area, serial.area, 1e-12);
  EXPECT_NEAR(parallel.l2, serial.l2, 1e-9 * serial.l2 + 1e-14);
}

INSTANTIATE_TEST_SUITE_P(Cells, MpiPoisson3d,
                         ::testing::Values(Case{CellType::hexahedron, 1, 5},
                                           Case{CellType::tetrahedron, 1, 4},
                                           Case{CellType::hexahedron, 2, 3},
                                           Case{CellType::tetrahedron, 2, 3}),
                         [](const auto& info) {
                           return to_string(info.param.type) + "_order" + std::to_string(info.param.order);
                         });

TEST(MpiMultigrid3d, TwoRanksEqualSerial) {
  for (const CellType type : {CellType::hexahedron, CellType::tetrahedron}) {
    const auto run = [&](MPI_Comm comm, VectorX& u) {
      multigrid::PoissonMultigridOptions o;
      o.linear.rtol = 1e-11;
      multigrid::PoissonMultigridSolver<3> mg(comm, unit_cube(2, type), 2, std::make_shared<BentCube>(), 1, 3,
                                              mixed_problem(), o);
      const auto report = mg.solve();
      u = mg.finest().distribution().gather_all(mg.finest().solution());
      return report.linear.iterations;
    };
    VectorX up, us;
    const int parallel = run(MPI_COMM_WORLD, up), serial = run(MPI_COMM_SELF, us);
    EXPECT_LE(std::abs(parallel - serial), 3) << to_string(type);
    EXPECT_LT((up - us).lpNorm<Eigen::Infinity>(), 1e-8 * us.lpNorm<Eigen::Infinity>()) << to_string(type);
  }
}
