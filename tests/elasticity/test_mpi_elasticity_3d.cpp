// Run under mpiexec -n 2: a distributed 3D neo-Hookean solve (quasi-static and
// transient, Newton's linear solves by LU or by GMRES + geometric multigrid)
// equals the serial one on every rank.

#include <gtest/gtest.h>
#include <petscsys.h>

#include <algorithm>
#include <string>
#include <utility>

#include "core/petsc/check.hpp"
#include "elasticity_3d_fixtures.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "fem/physics/elasticity/transient_solver.hpp"
#include "multigrid/geometric_multigrid.hpp"

using namespace warpfem;
using fem::MaterialModel;
using warpfem::CellType;

namespace {

struct Solution {
  VectorX u;
  double min_det_F = 0, strain_energy = 0;
  int newton_iterations = 0;
};

fem::ElasticityData<3> loaded_bar() {
  fem::ElasticityData<3> data = test::clamped_at_x0(MaterialModel::neo_hookean, 100.0, 0.3, 2.0);
  data.gravity = Point<3>(0, 0, -1);
  data.neumann.push_back({{1}, [](const Point<3>& x, double) { return Point<3>(0, -0.5, -1 - x.y()); }});
  return data;
}

Solution quasi_static(MPI_Comm comm, CellType type, int order) {
  const Mesh<3> mesh = test::box_mesh(Point<3>(2, 1, 1), {4, 2, 2}, type);
  const fem::HyperelasticOperator op(comm, mesh, std::make_shared<test::WarpedBoxMap>(), order, 0,
                                     loaded_bar());
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, test::quiet_newton(), {.steps = 2});
  const auto report = solver.solve(u.get());
  return {op.space().gather_all(u.get()), op.min_det_F(u.get()), op.strain_energy(u.get()),
          report.newton_iterations()};
}

Solution transient(MPI_Comm comm) {
  const Mesh<3> mesh = test::box_mesh(Point<3>(2, 1, 1), {4, 2, 2}, CellType::tetrahedron);
  const fem::HyperelasticOperator op(comm, mesh, std::make_shared<test::WarpedBoxMap>(), 1, 0, loaded_bar());
  petsc::Vector u = op.space().create_vector(), v = op.space().create_vector();
  fem::TransientOptions options;
  options.time_step = 0.05;
  options.end_time = 0.2;
  options.rho_infinity = 0.8;
  fem::TransientSolver solver(op, options, test::quiet_newton());
  const auto report = solver.solve(u.get(), v.get());
  return {op.space().gather_all(u.get()), op.min_det_F(u.get()), op.strain_energy(u.get()),
          report.newton_iterations};
}

/// Quasi-static on the finest level of a 3-level hierarchy, GMRES + GeometricMultigrid<3>;
/// `linear_iterations`: the most Krylov iterations of a Newton step.
Solution quasi_static_multigrid(MPI_Comm comm, CellType type, int order, int& linear_iterations) {
  const fem::MeshHierarchy<3> hierarchy(test::box_mesh(Point<3>(2, 1, 1), {2, 1, 1}, type), 2);
  const fem::HyperelasticOperator op(comm, hierarchy.finest(), std::make_shared<test::WarpedBoxMap>(), order,
                                     0, loaded_bar());
  const multigrid::GeometricMultigrid<3> mg(hierarchy, op);
  fem::NewtonOptions newton = test::quiet_newton();
  newton.rtol = 1e-10;
  newton.ksp_type = "gmres";
  newton.configure_preconditioner = [&mg](KSP ksp, Mat jacobian) {
    WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp, 1e-11, 1e-50, PETSC_DEFAULT, 200));
    mg.configure(ksp, {jacobian});
  };
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, newton, {.steps = 2});
  const auto report = solver.solve(u.get());
  linear_iterations = 0;
  for (const auto& step : report.steps)
    for (int its : step.linear_iterations) linear_iterations = std::max(linear_iterations, its);
  return {op.space().gather_all(u.get()), op.min_det_F(u.get()), op.strain_energy(u.get()),
          report.newton_iterations()};
}

void expect_equal(const Solution& parallel, const Solution& serial, const char* what) {
  ASSERT_EQ(parallel.u.size(), serial.u.size());
  ASSERT_GT(serial.u.norm(), 0);
  EXPECT_LT((parallel.u - serial.u).norm(), 1e-9 * serial.u.norm()) << what;
  EXPECT_NEAR(parallel.min_det_F, serial.min_det_F, 1e-10) << what;
  EXPECT_NEAR(parallel.strain_energy, serial.strain_energy, 1e-10 * serial.strain_energy) << what;
  EXPECT_EQ(parallel.newton_iterations, serial.newton_iterations) << what;
}

}  // namespace

TEST(MpiElasticity3d, RunsOnTwoRanks) {
  int size = 0;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  EXPECT_EQ(size, 2) << "run under mpiexec -n 2";
}

TEST(MpiElasticity3d, QuasiStaticOnHexahedraEqualsSerial) {
  expect_equal(quasi_static(PETSC_COMM_WORLD, CellType::hexahedron, 1),
               quasi_static(PETSC_COMM_SELF, CellType::hexahedron, 1), "Q1");
}

TEST(MpiElasticity3d, QuasiStaticOnTetrahedraEqualsSerial) {
  expect_equal(quasi_static(PETSC_COMM_WORLD, CellType::tetrahedron, 2),
               quasi_static(PETSC_COMM_SELF, CellType::tetrahedron, 2), "P2");
}

TEST(MpiElasticity3d, TransientEqualsSerial) {
  expect_equal(transient(PETSC_COMM_WORLD), transient(PETSC_COMM_SELF), "P1 transient");
}

TEST(MpiElasticity3d, MultigridNewtonEqualsSerial) {
  for (const auto& [type, order] : {std::pair{CellType::hexahedron, 1}, std::pair{CellType::tetrahedron, 1},
                                    std::pair{CellType::hexahedron, 2}}) {
    int parallel_its = 0, serial_its = 0;
    const Solution parallel = quasi_static_multigrid(PETSC_COMM_WORLD, type, order, parallel_its);
    const Solution serial = quasi_static_multigrid(PETSC_COMM_SELF, type, order, serial_its);
    const std::string what = to_string(type) + " order " + std::to_string(order) + " with multigrid";
    expect_equal(parallel, serial, what.c_str());
    // Chebyshev's eigenvalue estimates depend on the partition, so may a Krylov iteration or two.
    EXPECT_LE(std::abs(parallel_its - serial_its), 2) << what;
    EXPECT_GT(serial_its, 1) << what;
  }
}
