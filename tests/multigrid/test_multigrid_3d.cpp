// Geometric multigrid in 3D: PoissonMultigridSolver<3> on nested hierarchies
// of the unit cube (hexahedra, Bey-refined tetrahedra) under a smooth warp.
// CG iterations stay bounded as the mesh is refined, and the preconditioned
// solve gives the direct solution of the same finest system.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/petsc/check.hpp"
#include "core/petsc/linear_solve.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "tests/fem/poisson_3d_fixtures.hpp"

using namespace warpfem;
using namespace warpfem::testing3d;

namespace {

struct Case {
  CellType type;
  int order;
  int coarse_n;     ///< cells per side of level 0
  int refinements;  ///< of the finest hierarchy; iterations compared between the last two
  int max_iterations;
};

std::string name(const ::testing::TestParamInfo<Case>& info) {
  return to_string(info.param.type) + "_order" + std::to_string(info.param.order);
}

fem::PoissonData<3> cube_problem() {
  fem::PoissonData<3> data;
  data.source = [](const Point<3>& x, double) { return smooth_u(x); };
  data.dirichlet.push_back({.edges = {}, .value = [](const Point<3>& x, double) { return smooth_u(x); }});
  return data;
}

std::unique_ptr<multigrid::PoissonMultigridSolver<3>> make_solver(const Case& c, int refinements,
                                                                  multigrid::PoissonMultigridOptions o = {}) {
  o.linear.rtol = 1e-10;
  o.linear.max_iterations = 100;  // a broken preconditioner fails fast
  return std::make_unique<multigrid::PoissonMultigridSolver<3>>(MPI_COMM_SELF, unit_cube(c.coarse_n, c.type),
                                                                refinements, std::make_shared<BentCube>(),
                                                                c.order, 2 * c.order + 1, cube_problem(), o);
}

class Multigrid3d : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(Multigrid3d, IterationsAreNearlyLevelIndependent) {
  const Case c = GetParam();
  std::vector<int> its;
  for (int r = c.refinements - 1; r <= c.refinements; ++r) {
    auto mg = make_solver(c, r);
    const auto report = mg->solve();
    EXPECT_TRUE(report.linear.converged) << report.linear.converged_reason;
    EXPECT_EQ(report.levels, r + 1);
    its.push_back(report.linear.iterations);
  }
  EXPECT_LE(its.back(), c.max_iterations) << its.front() << " -> " << its.back();
  EXPECT_LE(its.back(), 1.5 * its.front()) << its.front() << " -> " << its.back();
}

TEST_P(Multigrid3d, SolutionEqualsTheDirectSolve) {
  const Case c = GetParam();
  auto mg = make_solver(c, c.refinements - 1);
  mg->solve();
  const fem::PoissonProblem<3>& p = mg->finest();
  petsc::Vector direct = p.create_vector();
  petsc::LinearSolveOptions lu;
  lu.direct_below = 1 << 30;  // LU whatever the size
  petsc::solve_linear_system(p.matrix(), p.rhs(), direct.get(), lu);
  PetscReal diff = 0, scale = 0;
  WARPFEM_PETSC_CHECK(VecNorm(direct.get(), NORM_INFINITY, &scale));
  WARPFEM_PETSC_CHECK(VecAXPY(direct.get(), -1.0, p.solution()));
  WARPFEM_PETSC_CHECK(VecNorm(direct.get(), NORM_INFINITY, &diff));
  EXPECT_LT(diff, 1e-7 * scale);
}

TEST(Multigrid3d, GalerkinCoarseOperatorsConvergeLikeRediscretizedOnes) {
  const Case c{CellType::hexahedron, 1, 2, 2, 15};
  multigrid::PoissonMultigridOptions o;
  o.multigrid.coarse_operators = multigrid::MultigridSettings::CoarseOperators::galerkin;
  auto galerkin = make_solver(c, c.refinements, o);
  auto rediscretized = make_solver(c, c.refinements);
  const int gi = galerkin->solve().linear.iterations, ri = rediscretized->solve().linear.iterations;
  EXPECT_LE(gi, ri + 3);
  EXPECT_LE(gi, c.max_iterations);
}

INSTANTIATE_TEST_SUITE_P(Cells, Multigrid3d,
                         ::testing::Values(Case{CellType::hexahedron, 1, 2, 3, 15},
                                           Case{CellType::tetrahedron, 1, 2, 3, 15},
                                           Case{CellType::hexahedron, 2, 1, 3, 15},
                                           Case{CellType::tetrahedron, 2, 1, 3, 15}),
                         name);

// The automatic smoother: Chebyshev–SOR for P2 on tetrahedra, Chebyshev–Jacobi
// (fused) for the other elements; an explicit choice is kept.
TEST(Multigrid3d, AutomaticSmootherDependsOnTheElement) {
  using S = multigrid::MultigridSettings;
  for (const Case& c : {Case{CellType::tetrahedron, 2, 1, 1, 15}, Case{CellType::tetrahedron, 1, 1, 1, 15},
                        Case{CellType::hexahedron, 2, 1, 1, 15}}) {
    const bool sor = c.type == CellType::tetrahedron && c.order == 2;
    auto mg = make_solver(c, c.refinements);
    EXPECT_EQ(mg->multigrid().settings().smoother,
              sor ? S::Smoother::chebyshev_sor : S::Smoother::chebyshev_jacobi)
        << to_string(c.type) << " P" << c.order;
    KSP smoother = nullptr;
    PC pc = nullptr, level_pc = nullptr;
    WARPFEM_PETSC_CHECK(KSPGetPC(mg->ksp(), &pc));
    WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, 1, &smoother));
    WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &level_pc));
    PetscBool is_sor = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(level_pc), PCSOR, &is_sor));
    EXPECT_EQ(is_sor == PETSC_TRUE, sor) << to_string(c.type) << " P" << c.order;
  }
  multigrid::PoissonMultigridOptions o;
  o.multigrid.smoother = S::Smoother::chebyshev_jacobi;
  auto mg = make_solver(Case{CellType::tetrahedron, 2, 1, 1, 15}, 1, o);
  EXPECT_EQ(mg->multigrid().settings().smoother, S::Smoother::chebyshev_jacobi);
}
