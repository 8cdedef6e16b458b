// One geometric multigrid for scalar and vector problems, through fem::Problem:
// - the Jacobian a problem reports is the derivative of its residual (Poisson
//   and elasticity alike), with identity rows at the constrained unknowns;
// - Galerkin levels built below the finest problem constrain the same coarse
//   DOFs as problems rediscretized on every level, so both give the same
//   prolongations.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/petsc/check.hpp"
#include "elasticity_multigrid_fixtures.hpp"
#include "fem/physics/poisson.hpp"
#include "multigrid/geometric_multigrid.hpp"
#include "multigrid/prolongation.hpp"
#include "multigrid_fixtures.hpp"

namespace warpfem::multigrid {
namespace {

/// max |J v − (R(u + εv) − R(u − εv)) / 2ε| / max |J v| over the free rows, for a random u and a
/// random v that is zero at the constrained unknowns.
double jacobian_mismatch(const fem::Problem<2>& problem, double u_scale) {
  petsc::Vector u = problem.create_vector(), v = problem.create_vector();
  petsc::Vector r_plus = problem.create_vector(), r_minus = problem.create_vector();
  petsc::Vector jv = problem.create_vector(), w = problem.create_vector();
  PetscRandom rnd;
  WARPFEM_PETSC_CHECK(PetscRandomCreate(problem.comm(), &rnd));
  WARPFEM_PETSC_CHECK(VecSetRandom(u.get(), rnd));
  WARPFEM_PETSC_CHECK(VecSetRandom(v.get(), rnd));
  WARPFEM_PETSC_CHECK(PetscRandomDestroy(&rnd));
  WARPFEM_PETSC_CHECK(VecScale(u.get(), u_scale));
  // The Jacobian's constrained columns are the identity's: compare along free directions.
  const auto constrained = problem.constrained();
  const fem::DofDistribution<2>& nodes = problem.nodes();
  const int k = problem.components();
  for (Index d = 0; d < problem.dofs().num_dofs(); ++d)
    for (int c = 0; c < k; ++c)
      if (nodes.owns(d) && constrained[static_cast<std::size_t>(c)][static_cast<std::size_t>(d)])
        WARPFEM_PETSC_CHECK(VecSetValue(v.get(), k * nodes.global(d) + c, 0.0, INSERT_VALUES));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(v.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(v.get()));
  petsc::Matrix J = problem.create_matrix();
  problem.jacobian(u.get(), {}, J.get());
  WARPFEM_PETSC_CHECK(MatMult(J.get(), v.get(), jv.get()));
  const double eps = 1e-6;
  WARPFEM_PETSC_CHECK(VecWAXPY(w.get(), eps, v.get(), u.get()));
  EXPECT_TRUE(problem.residual(w.get(), {}, r_plus.get()));
  WARPFEM_PETSC_CHECK(VecWAXPY(w.get(), -eps, v.get(), u.get()));
  EXPECT_TRUE(problem.residual(w.get(), {}, r_minus.get()));
  WARPFEM_PETSC_CHECK(VecAXPY(r_plus.get(), -1.0, r_minus.get()));
  WARPFEM_PETSC_CHECK(VecScale(r_plus.get(), 1.0 / (2 * eps)));
  // Constrained rows: the residual is u − g there, the Jacobian's row is the identity's.
  PetscScalar* fd = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(r_plus.get(), &fd));
  const PetscScalar* exact = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(jv.get(), &exact));
  double diff = 0, size = 0;
  for (Index d = 0; d < problem.dofs().num_dofs(); ++d) {
    if (!nodes.owns(d)) continue;
    for (int c = 0; c < k; ++c) {
      const PetscInt i = k * (nodes.global(d) - nodes.owned_begin()) + c;
      if (constrained[static_cast<std::size_t>(c)][static_cast<std::size_t>(d)]) continue;
      diff = std::max(diff, std::abs(exact[i] - fd[i]));
      size = std::max(size, std::abs(exact[i]));
    }
  }
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(jv.get(), &exact));
  WARPFEM_PETSC_CHECK(VecRestoreArray(r_plus.get(), &fd));
  MPI_Allreduce(MPI_IN_PLACE, &diff, 1, MPI_DOUBLE, MPI_MAX, problem.comm());
  MPI_Allreduce(MPI_IN_PLACE, &size, 1, MPI_DOUBLE, MPI_MAX, problem.comm());
  return diff / size;
}

TEST(Problem, PoissonJacobianIsTheDerivativeOfItsResidual) {
  const warpfem::Mesh<2> mesh = test::coarse_l_shape(warpfem::CellType::triangle, 0.25);
  fem::PoissonProblem<2> poisson(PETSC_COMM_WORLD, mesh, std::make_shared<mapping::IdentityMap<2>>(), 2, 6,
                                 test::mixed_problem());
  poisson.assemble();
  const fem::Problem<2>& problem = poisson;
  EXPECT_EQ(problem.components(), 1);
  EXPECT_LT(jacobian_mismatch(problem, 1.0), 1e-8);
}

TEST(Problem, ElasticityJacobianIsTheDerivativeOfItsResidual) {
  const warpfem::Mesh<2> mesh =
      warpfem::structured_mesh(test::unit_square(), 4, 4, warpfem::CellType::quadrilateral);
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, mesh, test::warped_square(), 2, 0,
                                     test::clamped_block());
  const fem::Problem<2>& problem = op;
  EXPECT_EQ(problem.components(), 2);
  // Small displacements keep det F > 0; the residual is nonlinear in them.
  EXPECT_LT(jacobian_mismatch(problem, 1e-2), 1e-6);
}

/// max |P_a − P_b| over the entries.
double difference(Mat a, Mat b) {
  petsc::Matrix d;
  WARPFEM_PETSC_CHECK(MatDuplicate(a, MAT_COPY_VALUES, d.out()));
  WARPFEM_PETSC_CHECK(MatAXPY(d.get(), -1.0, b, DIFFERENT_NONZERO_PATTERN));
  PetscReal norm = 0;
  WARPFEM_PETSC_CHECK(MatNorm(d.get(), NORM_INFINITY, &norm));
  return norm;
}

TEST(GeometricMultigrid, GalerkinLevelsConstrainWhatRediscretizedLevelsDo) {
  for (const int order : {1, 2}) {
    SCOPED_TRACE("P" + std::to_string(order));
    const fem::MeshHierarchy<2> h(test::coarse_l_shape(warpfem::CellType::triangle, 0.5), 2);
    const auto map = std::make_shared<mapping::IdentityMap<2>>();
    const fem::PoissonData<2> data = test::mixed_problem();
    const auto owners = fem::nested_partitions(h, 1);
    std::vector<std::unique_ptr<fem::PoissonProblem<2>>> problems;
    std::vector<const fem::Problem<2>*> levels;
    for (int l = 0; l < h.num_levels(); ++l) {
      problems.push_back(std::make_unique<fem::PoissonProblem<2>>(
          MPI_COMM_SELF, h.levels[static_cast<std::size_t>(l)], map, order, 2 * order + 2, data,
          fem::GeometryStorage::cached, owners[static_cast<std::size_t>(l)]));
      levels.push_back(problems.back().get());
    }
    const GeometricMultigrid rediscretized(h, levels, MultigridSettings{});
    const GeometricMultigrid galerkin(h, *problems.back(), GeometricMultigrid<2>::galerkin_defaults(),
                                      owners);
    ASSERT_EQ(galerkin.num_levels(), 3);
    ASSERT_EQ(galerkin.components(), 1);
    for (int l = 1; l < 3; ++l) {
      EXPECT_EQ(difference(rediscretized.prolongation(l), galerkin.prolongation(l)), 0.0) << "level " << l;
      PetscReal norm = 0;
      WARPFEM_PETSC_CHECK(MatNorm(galerkin.prolongation(l), NORM_INFINITY, &norm));
      EXPECT_GT(norm, 0.5);
    }
  }
}

TEST(GeometricMultigrid, VectorProlongationIsTheScalarOnePerComponent) {
  // Elasticity clamped at the bottom, roller (u_x only) on the left: component c
  // of the vector prolongation is the scalar one with component c's constrained DOFs.
  const fem::MeshHierarchy<2> h(
      warpfem::structured_mesh(test::unit_square(), 3, 3, warpfem::CellType::triangle), 1);
  const fem::HyperelasticOperator op(PETSC_COMM_SELF, h.finest(), test::warped_square(), 1, 0,
                                     test::clamped_block());
  const GeometricMultigrid vector(h, op);
  ASSERT_EQ(vector.components(), 2);
  const auto constrained = op.constrained();
  for (int c = 0; c < 2; ++c) {
    // The scalar prolongation with component c's constrained DOFs.
    const fem::DofMap<2> coarse_dofs(h.levels[0], op.dofs().element());
    const fem::DofDistribution<2> coarse_nodes(MPI_COMM_SELF, h.levels[0], coarse_dofs);
    std::vector<char> coarse_mask(static_cast<std::size_t>(coarse_dofs.num_dofs()));
    for (Index d = 0; d < coarse_dofs.num_dofs(); ++d)
      coarse_mask[static_cast<std::size_t>(d)] = constrained[static_cast<std::size_t>(
          c)][static_cast<std::size_t>(h.transfers[0].fine_vertex_of_node[static_cast<std::size_t>(d)])];
    const petsc::Matrix scalar = assemble_prolongation(
        h, 1, {.dofs = &coarse_dofs, .distribution = &coarse_nodes, .dirichlet = coarse_mask},
        {.dofs = &op.dofs(),
         .distribution = &op.nodes(),
         .dirichlet = constrained[static_cast<std::size_t>(c)]});
    for (Index i = 0; i < op.dofs().num_dofs(); ++i)
      for (Index j = 0; j < coarse_dofs.num_dofs(); ++j) {
        PetscScalar s = 0, v = 0;
        const PetscInt si = op.nodes().global(i), sj = coarse_nodes.global(j);
        const PetscInt vs = vector.coarse_distribution(0).global(j);
        const PetscInt vi = 2 * si + c, vj = 2 * vs + c, vk = 2 * vs + (1 - c);
        WARPFEM_PETSC_CHECK(MatGetValues(scalar.get(), 1, &si, 1, &sj, &s));
        WARPFEM_PETSC_CHECK(MatGetValues(vector.prolongation(1), 1, &vi, 1, &vj, &v));
        ASSERT_EQ(s, v) << "component " << c << ", (" << i << ", " << j << ")";
        WARPFEM_PETSC_CHECK(MatGetValues(vector.prolongation(1), 1, &vi, 1, &vk, &v));
        ASSERT_EQ(v, 0.0) << "components coupled at (" << i << ", " << j << ")";
      }
  }
}

}  // namespace
}  // namespace warpfem::multigrid
