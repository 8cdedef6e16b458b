// Geometric multigrid for elasticity's Newton steps (multigrid/geometric_multigrid, Galerkin levels):
// the preconditioned Krylov solve gives the direct solver's answer, and the
// iteration count does not grow with refinement.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "elasticity_multigrid_fixtures.hpp"

namespace warpfem::multigrid {
namespace {

using test::clamped_block;
using test::solve_both;
using test::SolveResult;
using test::warped_square;

class ElasticityMultigridTest : public ::testing::TestWithParam<std::tuple<warpfem::CellType, int>> {};

TEST_P(ElasticityMultigridTest, MatchesLuWithIterationsIndependentOfRefinement) {
  const auto [type, order] = GetParam();
  int fewest = 1 << 30, most = 0;
  for (int refinements = 1; refinements <= 3; ++refinements) {
    const SolveResult r = solve_both(type, order, refinements);
    std::printf("[ %s%d, %d refinements ] %d GMRES iterations, |x_mg - x_lu| / |x_lu| = %.2e\n",
                type == warpfem::CellType::triangle ? "P" : "Q", order, refinements, r.iterations,
                r.relative_difference);
    EXPECT_LT(r.relative_difference, 1e-7);
    fewest = std::min(fewest, r.iterations);
    most = std::max(most, r.iterations);
  }
  EXPECT_LE(most, 30);
  EXPECT_LE(most - fewest, 5) << "the iteration count grows with refinement";
}

INSTANTIATE_TEST_SUITE_P(Elements, ElasticityMultigridTest,
                         ::testing::Values(std::make_tuple(warpfem::CellType::triangle, 1),
                                           std::make_tuple(warpfem::CellType::triangle, 2),
                                           std::make_tuple(warpfem::CellType::quadrilateral, 2)));

TEST(ElasticityMultigrid, RefusesASpaceOffTheHierarchy) {
  const fem::MeshHierarchy<2> hierarchy(
      warpfem::structured_mesh(test::unit_square(), 2, 2, warpfem::CellType::triangle), 1);
  const warpfem::Mesh<2> other = hierarchy.finest();  // a copy: not the hierarchy's mesh
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, other, warped_square(), 1, 0, clamped_block());
  EXPECT_THROW(GeometricMultigrid(hierarchy, op), Error);
}

TEST(ElasticityMultigrid, TakesCellOwnersForEveryLevelOrNone) {
  const fem::MeshHierarchy<2> hierarchy(
      warpfem::structured_mesh(test::unit_square(), 2, 2, warpfem::CellType::triangle), 2);
  const auto owners = fem::nested_partitions(hierarchy, 1);
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, hierarchy.finest(), warped_square(), 1, 0,
                                     clamped_block(), owners.back());
  EXPECT_NO_THROW(GeometricMultigrid(hierarchy, op, GeometricMultigrid<2>::galerkin_defaults(), owners));
  const std::vector<std::vector<int>> too_few(owners.begin(), owners.end() - 1);
  EXPECT_THROW(GeometricMultigrid(hierarchy, op, GeometricMultigrid<2>::galerkin_defaults(), too_few), Error);
}

}  // namespace
}  // namespace warpfem::multigrid
