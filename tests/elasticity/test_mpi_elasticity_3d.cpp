// Run under mpiexec -n 2: a distributed 3D neo-Hookean solve (quasi-static and
// transient) equals the serial one on every rank.

#include <gtest/gtest.h>
#include <petscsys.h>

#include "core/petsc/check.hpp"
#include "elasticity_3d_fixtures.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "fem/physics/elasticity/transient_solver.hpp"

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
