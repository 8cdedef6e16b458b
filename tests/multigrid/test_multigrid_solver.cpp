// Geometric multigrid as a preconditioner: iteration counts bounded
// independently of h, on the L-shape with its re-entrant corner.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/petsc/check.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "multigrid_fixtures.hpp"

using namespace warpfem;
using multigrid::test::coarse_l_shape;

namespace {

struct Case {
  warpfem::CellType type;
  int order;
  int max_iterations;
};

std::string name(const ::testing::TestParamInfo<Case>& info) {
  return (info.param.type == warpfem::CellType::triangle ? "P" : "Q") + std::to_string(info.param.order);
}

/// ‖b − A u‖ / ‖b‖ of the finest level, computed independently of the KSP.
double relative_residual(const fem::PoissonProblem<2>& p) {
  petsc::Vector r;
  WARPFEM_PETSC_CHECK(VecDuplicate(p.rhs(), r.out()));
  WARPFEM_PETSC_CHECK(MatMult(p.matrix(), p.solution(), r.get()));
  WARPFEM_PETSC_CHECK(VecAYPX(r.get(), -1.0, p.rhs()));
  PetscReal rn = 0, bn = 0;
  WARPFEM_PETSC_CHECK(VecNorm(r.get(), NORM_2, &rn));
  WARPFEM_PETSC_CHECK(VecNorm(p.rhs(), NORM_2, &bn));
  return rn / bn;
}

/// A smooth bijective warp f(x) = x + 0.1 (sin πy, sin πx): Lipschitz perturbation 0.1π < 1 of the identity.
class SineWarp final : public mapping::Map<2> {
 public:
  void eval(const Points<2>& x0, Points<2>& x) const override {
    x.resize(x0.rows(), 2);
    for (Index p = 0; p < x0.rows(); ++p) {
      x(p, 0) = x0(p, 0) + 0.1 * std::sin(M_PI * x0(p, 1));
      x(p, 1) = x0(p, 1) + 0.1 * std::sin(M_PI * x0(p, 0));
    }
  }
  void jacobian(const Points<2>& x0, Jacobians<2>& J) const override {
    J.resize(x0.rows(), 4);
    for (Index p = 0; p < x0.rows(); ++p) {
      J(p, 0) = 1, J(p, 1) = 0.1 * M_PI * std::cos(M_PI * x0(p, 1));
      J(p, 2) = 0.1 * M_PI * std::cos(M_PI * x0(p, 0)), J(p, 3) = 1;
    }
  }
  std::string describe() const override { return "sine warp"; }
};

multigrid::MultigridSolveReport solve(const Case& c, int refinements, multigrid::PoissonMultigridOptions o,
                                      double* residual = nullptr, mapping::MapPtr<2> map = nullptr) {
  o.linear.max_iterations = 100;  // a broken preconditioner fails fast
  if (!map) map = std::make_shared<mapping::IdentityMap<2>>();
  multigrid::PoissonMultigridSolver<2> mg(MPI_COMM_SELF, coarse_l_shape(c.type, 0.5), refinements, map,
                                          c.order, 2 * c.order + 1, multigrid::test::mixed_problem(), o);
  auto report = mg.solve();
  if (residual) *residual = relative_residual(mg.finest());
  return report;
}

}  // namespace

class MultigridIterations : public ::testing::TestWithParam<Case> {};

TEST_P(MultigridIterations, AreBoundedIndependentlyOfMeshSize) {
  const Case c = GetParam();
  std::vector<int> its;
  for (int r = 1; r <= 4; ++r) {
    double residual = 0;
    const auto report = solve(c, r, {}, &residual);
    its.push_back(report.linear.iterations);
    std::printf("%s, %d levels, %lld DOFs: %d iterations\n", name({c, 0}).c_str(), report.levels,
                static_cast<long long>(report.level_dofs.back()), report.linear.iterations);
    EXPECT_LE(residual, 1.01e-8) << "the reported convergence is not a true relative residual of 1e-8";
    EXPECT_LE(report.linear.iterations, c.max_iterations) << "at " << report.levels << " levels";
  }
  const auto [lo, hi] = std::minmax_element(its.begin(), its.end());
  EXPECT_LE(*hi - *lo, 2) << "iteration counts grow with the number of levels";
}

INSTANTIATE_TEST_SUITE_P(Elements, MultigridIterations,
                         ::testing::Values(Case{warpfem::CellType::triangle, 1, 12},
                                           Case{warpfem::CellType::triangle, 2, 15},
                                           Case{warpfem::CellType::quadrilateral, 1, 12},
                                           Case{warpfem::CellType::quadrilateral, 2, 15}),
                         name);

// The warped problem (curved cells, J = J_f J_G at every quadrature point) keeps the h-independence.
TEST(MultigridIterationsOnWarpedGeometry, AreBoundedIndependentlyOfMeshSize) {
  const auto warp = std::make_shared<SineWarp>();
  for (const Case c : {Case{warpfem::CellType::triangle, 1, 12}, Case{warpfem::CellType::triangle, 2, 15}}) {
    std::vector<int> its;
    for (int r = 1; r <= 4; ++r) {
      double residual = 0;
      its.push_back(solve(c, r, {}, &residual, warp).linear.iterations);
      EXPECT_LE(residual, 1.01e-8);
      EXPECT_LE(its.back(), c.max_iterations);
    }
    std::printf("%s on the sine warp: %d %d %d %d iterations\n", name({c, 0}).c_str(), its[0], its[1], its[2],
                its[3]);
    const auto [lo, hi] = std::minmax_element(its.begin(), its.end());
    EXPECT_LE(*hi - *lo, 2) << name({c, 0}) << ": " << its[0] << " " << its[1] << " " << its[2] << " "
                            << its[3];
  }
}

TEST(MultigridVariants, SorChebyshevSorWCycleFCycleAndGalerkinAllConvergeQuickly) {
  using S = multigrid::MultigridSettings;
  const Case p2{warpfem::CellType::triangle, 2, 15};
  for (const S s :
       {S{.smoother = S::Smoother::sor}, S{.smoother = S::Smoother::chebyshev_sor}, S{.cycle = S::Cycle::w},
        S{.cycle = S::Cycle::f}, S{.coarse_operators = S::CoarseOperators::galerkin}}) {
    multigrid::PoissonMultigridOptions o;
    o.multigrid = s;
    double residual = 0;
    const auto report = solve(p2, 3, o, &residual);
    EXPECT_LE(residual, 1.01e-8);
    EXPECT_LE(report.linear.iterations, 15);
    EXPECT_EQ(report.linear.pc_type, "mg");
  }
}

// The smoother setting reaches every level's KSP (Chebyshev + SOR for chebyshev_sor).
TEST(MultigridVariants, ChebyshevSorSettingConfiguresEveryLevel) {
  using S = multigrid::MultigridSettings;
  multigrid::PoissonMultigridOptions o;
  o.multigrid = S{.smoother = S::Smoother::chebyshev_sor};
  multigrid::PoissonMultigridSolver<2> mg(MPI_COMM_SELF, coarse_l_shape(warpfem::CellType::triangle, 0.5), 2,
                                          std::make_shared<mapping::IdentityMap<2>>(), 1, 3,
                                          multigrid::test::mixed_problem(), o);
  PC pc = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetPC(mg.ksp(), &pc));
  for (PetscInt l = 1; l <= 2; ++l) {
    KSP smoother = nullptr;
    PC spc = nullptr;
    KSPType ktype = nullptr;
    PCType ptype = nullptr;
    WARPFEM_PETSC_CHECK(PCMGGetSmoother(pc, l, &smoother));
    WARPFEM_PETSC_CHECK(KSPGetType(smoother, &ktype));
    WARPFEM_PETSC_CHECK(KSPGetPC(smoother, &spc));
    WARPFEM_PETSC_CHECK(PCGetType(spc, &ptype));
    EXPECT_STREQ(ktype, KSPCHEBYSHEV) << "level " << l;
    EXPECT_STREQ(ptype, PCSOR) << "level " << l;
  }
}

TEST(MultigridSolver, RejectsNegativeRefinements) {
  EXPECT_THROW(solve({warpfem::CellType::triangle, 1, 12}, -1, {}), Error);
}

// Coarse levels always stream their geometry; streaming the finest one too must
// not change the multigrid solve (same operators, same iterations, same solution).
TEST(MultigridGeometryStorage, StreamedFinestLevelGivesTheCachedSolution) {
  const auto warp = std::make_shared<SineWarp>();
  const Case p2{warpfem::CellType::triangle, 2, 15};
  auto run = [&](fem::GeometryStorage storage, petsc::Vector& u) {
    multigrid::PoissonMultigridOptions o;
    o.finest_geometry = storage;
    multigrid::PoissonMultigridSolver<2> mg(MPI_COMM_SELF, coarse_l_shape(p2.type, 0.5), 2, warp, p2.order,
                                            2 * p2.order + 1, multigrid::test::mixed_problem(), o);
    EXPECT_EQ(mg.finest().geometry().storage(), storage);
    const auto report = mg.solve();
    WARPFEM_PETSC_CHECK(VecDuplicate(mg.finest().solution(), u.out()));
    WARPFEM_PETSC_CHECK(VecCopy(mg.finest().solution(), u.get()));
    return report.linear.iterations;
  };
  petsc::Vector cached, streamed;
  const int its_cached = run(fem::GeometryStorage::cached, cached);
  const int its_streamed = run(fem::GeometryStorage::streamed, streamed);
  EXPECT_EQ(its_streamed, its_cached);
  PetscReal norm = 0, diff = 0;
  WARPFEM_PETSC_CHECK(VecNorm(cached.get(), NORM_2, &norm));
  WARPFEM_PETSC_CHECK(VecAXPY(streamed.get(), -1.0, cached.get()));
  WARPFEM_PETSC_CHECK(VecNorm(streamed.get(), NORM_2, &diff));
  EXPECT_LE(diff, 1e-12 * norm);
}

// The run frees the solver before its output; what the output and the report
// read of the finest problem (solution, errors through the geometry, area) must
// stay as it was, with the geometry evaluated again instead of cached.
TEST(MultigridSolver, ReleasingTheSolverKeepsTheSolutionAndTheErrors) {
  const auto warp = std::make_shared<SineWarp>();
  multigrid::PoissonMultigridSolver<2> mg(MPI_COMM_SELF, coarse_l_shape(warpfem::CellType::triangle, 0.5), 2,
                                          warp, 1, 2, multigrid::test::mixed_problem(), {});
  mg.solve();
  const fem::ScalarFunction<2> u = [](const Point<2>& x, double) { return std::sin(x(0)) * x(1); };
  const fem::GradientFunction<2> grad_u = [](const Point<2>& x, double) {
    return Point<2>(std::cos(x(0)) * x(1), std::sin(x(0)));
  };
  const fem::PoissonProblem<2>& finest = mg.finest();
  const auto before = finest.errors(u, grad_u);
  const double area_before = finest.area();
  petsc::Vector solved;
  WARPFEM_PETSC_CHECK(VecDuplicate(finest.solution(), solved.out()));
  WARPFEM_PETSC_CHECK(VecCopy(finest.solution(), solved.get()));
  ASSERT_EQ(finest.geometry().storage(), fem::GeometryStorage::cached);

  mg.release_solver();
  EXPECT_EQ(mg.ksp(), nullptr);
  EXPECT_EQ(finest.geometry().storage(), fem::GeometryStorage::streamed);
  EXPECT_EQ(finest.matrix(), nullptr);
  const auto after = finest.errors(u, grad_u);
  EXPECT_NEAR(after.l2, before.l2, 1e-14 * before.l2);
  EXPECT_NEAR(after.h1_semi, before.h1_semi, 1e-14 * before.h1_semi);
  EXPECT_NEAR(finest.area(), area_before, 1e-14 * area_before);
  PetscBool same = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(VecEqual(finest.solution(), solved.get(), &same));
  EXPECT_TRUE(same);
}
