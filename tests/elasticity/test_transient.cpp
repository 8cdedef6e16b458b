// Generalized-α elastodynamics: energy conservation of the non-dissipative member.

#include <gtest/gtest.h>

#include "elasticity_fixtures.hpp"
#include "fem/physics/elasticity/transient_solver.hpp"

using namespace warpfem;
using fem::MaterialModel;
using warpfem::CellType;

namespace {

struct EnergyRun {
  std::vector<double> energy;
  fem::TransientReport report;
};

EnergyRun swinging_beam(MaterialModel model, double rho_infinity, int steps) {
  const warpfem::Mesh<2> mesh = test::block_mesh(1, 1, 2, 2, CellType::triangle, 1);
  fem::ElasticityData<2> data;
  data.material = fem::Material::from_young_poisson(model, 10.0, 0.3, 1.0);
  const fem::ScalarFunction<2> zero = [](const Point<2>&, double) { return 0.0; };
  data.dirichlet.push_back({{3}, {zero, zero}});
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::warped_square_map(), 2, 0, data);
  petsc::Vector u = op.space().create_vector(), v = op.space().create_vector();
  // Initial velocity: a transverse swing growing away from the clamped edge.
  const VectorX nodes = VectorX::Zero(1);
  Points<2> x0 = op.space().dofs().dof_points(), x;
  op.map().eval(x0, x);
  for (Index d = 0; d < op.space().dofs().num_dofs(); ++d) {
    const PetscInt row = op.space().global(d, 1);
    const PetscScalar value = 0.3 * x(d, 0) * x(d, 0);
    WARPFEM_PETSC_CHECK(VecSetValues(v.get(), 1, &row, &value, INSERT_VALUES));
  }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(v.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(v.get()));
  fem::TransientOptions options;
  options.time_step = 0.02;
  options.end_time = steps * options.time_step;
  options.rho_infinity = rho_infinity;
  options.compute_energy = true;
  fem::NewtonOptions newton;
  newton.rtol = 1e-13;
  newton.atol = 1e-14;
  newton.log_iterations = false;
  fem::TransientSolver solver(op, options, newton);
  EnergyRun run;
  run.report = solver.solve(u.get(), v.get(), [&](const fem::TransientStep& s, Vec, Vec) {
    run.energy.push_back(s.total_energy());
  });
  return run;
}

}  // namespace

TEST(Transient, UndampedGeneralizedAlphaConservesEnergyOfLinearElasticity) {
  const EnergyRun run = swinging_beam(MaterialModel::linear_elastic, 1.0, 100);
  ASSERT_EQ(run.energy.size(), 101u) << "step 0 and 100 steps";
  EXPECT_EQ(run.report.steps, 100);
  const double e0 = run.energy.front();
  ASSERT_GT(e0, 0);
  double drift = 0;
  for (double e : run.energy) drift = std::max(drift, std::abs(e - e0) / e0);
  EXPECT_LT(drift, 1e-8) << "max relative energy drift over 100 steps";
}

TEST(Transient, NumericalDissipationWithRhoInfinityBelowOne) {
  const EnergyRun run = swinging_beam(MaterialModel::linear_elastic, 0.3, 100);
  EXPECT_LT(run.energy.back(), run.energy.front() * (1 - 1e-4)) << "ρ∞ < 1 must dissipate energy";
}

TEST(Transient, NeoHookeanEnergyStaysBounded) {
  const EnergyRun run = swinging_beam(MaterialModel::neo_hookean, 1.0, 50);
  const double e0 = run.energy.front();
  for (double e : run.energy) EXPECT_NEAR(e, e0, 0.02 * e0);
}
