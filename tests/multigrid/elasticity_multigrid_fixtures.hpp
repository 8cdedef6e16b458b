#pragma once
// The elasticity multigrid test problem (serial and MPI tests): a warped unit
// square, clamped at the bottom with a roller on the left, and one linear solve
// J(0) x = b by LU and by GMRES preconditioned with multigrid::GeometricMultigrid (Galerkin levels).

#include <gtest/gtest.h>

#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/elasticity/hyperelastic_operator.hpp"
#include "mapping/make_map.hpp"
#include "multigrid/geometric_multigrid.hpp"

namespace warpfem::multigrid::test {

inline Polygon unit_square() {
  return Polygon({Point<2>(0, 0), Point<2>(1, 0), Point<2>(1, 1), Point<2>(0, 1)}, "square");
}

inline mapping::MapPtr<2> warped_square() {
  mapping::MapSpec spec;
  spec.type = "barycentric";
  spec.source = unit_square();
  spec.target =
      Polygon({Point<2>(0, 0), Point<2>(1.1, 0.1), Point<2>(1.2, 1.0), Point<2>(-0.1, 0.9)}, "target");
  return mapping::make_map(spec);
}

/// Clamped bottom edge, roller (u_x = 0) on the left edge, the rest free.
inline fem::ElasticityData<2> clamped_block() {
  fem::ElasticityData<2> data;
  data.material = fem::Material::from_young_poisson(fem::MaterialModel::neo_hookean, 1000.0, 0.3, 1.0);
  const fem::ScalarFunction<2> zero = [](const Point<2>&, double) { return 0.0; };
  data.dirichlet.push_back({.edges = {0}, .value = {zero, zero}});
  data.dirichlet.push_back({.edges = {3}, .value = {zero, nullptr}});
  return data;
}

struct SolveResult {
  int iterations = 0;
  double relative_difference = 0;  ///< ‖x_mg − x_lu‖ / ‖x_lu‖
};

/// Solves J(0) x = b (b random, zero on constrained rows) with LU and with GMRES + multigrid.
inline SolveResult solve_both(warpfem::CellType type, int order, int refinements) {
  const fem::MeshHierarchy<2> hierarchy(
      warpfem::structured_mesh(
          Polygon({Point<2>(0, 0), Point<2>(1, 0), Point<2>(1, 1), Point<2>(0, 1)}, "square"), 4, 4, type),
      refinements);
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, hierarchy.finest(), warped_square(), order, 0,
                                     clamped_block());
  const GeometricMultigrid mg(hierarchy, op);
  petsc::Matrix J = op.space().create_matrix();
  petsc::Vector u = op.space().create_vector(), b = op.space().create_vector();
  petsc::Vector x_lu = op.space().create_vector(), x_mg = op.space().create_vector();
  WARPFEM_PETSC_CHECK(VecSet(u.get(), 0.0));
  op.jacobian(u.get(), 0.0, J.get());
  PetscRandom rnd;
  WARPFEM_PETSC_CHECK(PetscRandomCreate(PETSC_COMM_WORLD, &rnd));
  WARPFEM_PETSC_CHECK(VecSetRandom(b.get(), rnd));
  WARPFEM_PETSC_CHECK(PetscRandomDestroy(&rnd));
  op.zero_constrained(b.get());

  petsc::LinearSolver lu, gmres;
  WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_WORLD, lu.out()));
  WARPFEM_PETSC_CHECK(KSPSetOperators(lu.get(), J.get(), J.get()));
  WARPFEM_PETSC_CHECK(KSPSetType(lu.get(), KSPPREONLY));
  PC pc;
  WARPFEM_PETSC_CHECK(KSPGetPC(lu.get(), &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, PCLU));
  WARPFEM_PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  WARPFEM_PETSC_CHECK(KSPSolve(lu.get(), b.get(), x_lu.get()));

  WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_WORLD, gmres.out()));
  WARPFEM_PETSC_CHECK(KSPSetType(gmres.get(), KSPGMRES));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(gmres.get(), 1e-10, 1e-50, PETSC_DEFAULT, 500));
  mg.configure(gmres.get(), {J.get()});
  WARPFEM_PETSC_CHECK(KSPSolve(gmres.get(), b.get(), x_mg.get()));
  KSPConvergedReason reason;
  WARPFEM_PETSC_CHECK(KSPGetConvergedReason(gmres.get(), &reason));
  EXPECT_GT(reason, 0) << "GMRES + multigrid did not converge";
  PetscInt its = 0;
  WARPFEM_PETSC_CHECK(KSPGetIterationNumber(gmres.get(), &its));

  PetscReal nlu = 0, ndiff = 0;
  WARPFEM_PETSC_CHECK(VecNorm(x_lu.get(), NORM_2, &nlu));
  WARPFEM_PETSC_CHECK(VecAXPY(x_mg.get(), -1.0, x_lu.get()));
  WARPFEM_PETSC_CHECK(VecNorm(x_mg.get(), NORM_2, &ndiff));
  return {static_cast<int>(its), ndiff / nlu};
}

}  // namespace warpfem::multigrid::test
