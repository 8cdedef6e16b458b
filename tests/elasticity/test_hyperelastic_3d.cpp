// The hyperelastic operator and its solvers in 3D, through the same templates
// as 2D: consistent Jacobian (P1/P2 tetrahedra, Q1/Q2 hexahedra, identity and
// a warped map), the patch test of a homogeneous deformation, a cantilever
// against beam theory, quadratic Newton convergence and the energy of the
// generalized-α scheme.

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>

#include "core/petsc/check.hpp"
#include "elasticity_3d_fixtures.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "fem/physics/elasticity/transient_solver.hpp"

using namespace warpfem;
using fem::MaterialModel;
using warpfem::CellType;

namespace {

/// A number for RecordProperty (visible with --gtest_output=xml).
std::string sci(double x) {
  std::ostringstream os;
  os << std::scientific << std::setprecision(4) << x;
  return os.str();
}

struct JacobianCase {
  CellType type;
  int order;
  bool warped;
  const char* name;
};

class OperatorJacobian3d : public ::testing::TestWithParam<JacobianCase> {};

}  // namespace

TEST_P(OperatorJacobian3d, MatchesFiniteDifferencesOfTheResidual) {
  const auto& param = GetParam();
  const Mesh<3> mesh = test::box_mesh(Point<3>(1, 1, 1), {2, 2, 2}, param.type);
  fem::ElasticityData<3> data = test::clamped_at_x0(MaterialModel::neo_hookean);
  data.gravity = Point<3>(0, 0, -2);
  data.neumann.push_back({{1}, [](const Point<3>& x, double) { return Point<3>(0.1, 0, -0.2 * x.y()); }});
  const mapping::MapPtr<3> map =
      param.warped ? std::make_shared<test::WarpedBoxMap>() : test::identity_map_3d();
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, map, param.order, 0, data);
  const auto& space = op.space();
  petsc::Vector u = space.create_vector(), du = space.create_vector(), up = space.create_vector(),
                um = space.create_vector(), rp = space.create_vector(), rm = space.create_vector(),
                jdu = space.create_vector();
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> dist(-1, 1);
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(u.get(), &a));
  for (PetscInt i = 0; i < space.num_owned(); ++i) a[i] = 0.02 * dist(gen);
  WARPFEM_PETSC_CHECK(VecRestoreArray(u.get(), &a));
  WARPFEM_PETSC_CHECK(VecGetArray(du.get(), &a));
  for (PetscInt i = 0; i < space.num_owned(); ++i) a[i] = dist(gen);
  WARPFEM_PETSC_CHECK(VecRestoreArray(du.get(), &a));
  op.zero_constrained(du.get());  // the constrained rows are the identity on both sides
  ASSERT_GT(op.min_det_F(u.get()), 0.5);
  ASSERT_GT(op.num_constrained(), 0);

  petsc::Matrix J = space.create_matrix();
  op.jacobian(u.get(), 0.0, J.get());
  WARPFEM_PETSC_CHECK(MatMult(J.get(), du.get(), jdu.get()));
  const double h = 1e-6;
  WARPFEM_PETSC_CHECK(VecWAXPY(up.get(), h, du.get(), u.get()));
  WARPFEM_PETSC_CHECK(VecWAXPY(um.get(), -h, du.get(), u.get()));
  ASSERT_TRUE(op.residual(up.get(), nullptr, 1.0, 0.0, rp.get()));
  ASSERT_TRUE(op.residual(um.get(), nullptr, 1.0, 0.0, rm.get()));
  const VectorX fd = (space.gather_all(rp.get()) - space.gather_all(rm.get())) / (2 * h);
  const VectorX exact = space.gather_all(jdu.get());
  const double rel = (fd - exact).norm() / exact.norm();
  EXPECT_LE(rel, 1e-6) << param.name << ": relative difference " << rel;
  RecordProperty("jacobian_vs_fd", sci(rel));

  // The residual is the gradient of the potential energy on the free unknowns.
  const double e_p = *op.potential_energy(up.get(), 1.0, 0.0), e_m = *op.potential_energy(um.get(), 1.0, 0.0);
  ASSERT_TRUE(op.residual(u.get(), nullptr, 1.0, 0.0, rp.get()));
  PetscScalar r_du = 0;
  WARPFEM_PETSC_CHECK(VecDot(rp.get(), du.get(), &r_du));
  EXPECT_NEAR((e_p - e_m) / (2 * h), r_du, 1e-6 * std::abs(r_du)) << param.name;
}

INSTANTIATE_TEST_SUITE_P(Elements, OperatorJacobian3d,
                         ::testing::Values(JacobianCase{CellType::tetrahedron, 1, false, "P1"},
                                           JacobianCase{CellType::tetrahedron, 2, false, "P2"},
                                           JacobianCase{CellType::hexahedron, 1, false, "Q1"},
                                           JacobianCase{CellType::hexahedron, 2, false, "Q2"},
                                           JacobianCase{CellType::tetrahedron, 2, true, "P2_warped"},
                                           JacobianCase{CellType::hexahedron, 1, true, "Q1_warped"}),
                         [](const auto& info) { return std::string(info.param.name); });

// A homogeneous material under a prescribed affine displacement on the whole boundary
// and no body force is in equilibrium at the affine field (constant F, constant P,
// div P = 0): the discrete solution must reproduce it at every node, also on
// distorted cells.
TEST(QuasiStatic3d, PatchTestReproducesAHomogeneousDeformation) {
  Matrix<3> G;
  G << 1.1, 0.2, 0.0, 0.05, 0.9, 0.1, 0.0, -0.1, 1.05;
  const Point<3> c(0.01, -0.02, 0.03);
  const auto affine = [&](const Point<3>& x) -> Point<3> { return (G - Matrix<3>::Identity()) * x + c; };
  for (const auto& [type, order] :
       {std::pair{CellType::hexahedron, 1}, std::pair{CellType::tetrahedron, 2}}) {
    Mesh<3> mesh = test::box_mesh(Point<3>(1, 1, 1), {3, 3, 3}, type);
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> jitter(-0.05, 0.05);  // of a cell width 1/3
    for (Index v = 0; v < mesh.num_vertices(); ++v) {
      const Point<3> x = mesh.vertex(v);
      if ((x.array() > 1e-12).all() && (x.array() < 1 - 1e-12).all())
        for (int i = 0; i < 3; ++i) mesh.vertices(v, i) += jitter(gen);
    }
    fem::ElasticityData<3> data;
    data.material = fem::Material::from_young_poisson(MaterialModel::neo_hookean, 10.0, 0.3);
    fem::DisplacementCondition<3> all;  // no parts listed: the whole boundary
    for (int i = 0; i < 3; ++i) all.value[i] = [&, i](const Point<3>& x, double) { return affine(x)(i); };
    data.dirichlet.push_back(all);
    const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::identity_map_3d(), order, 0, data);
    petsc::Vector u = op.space().create_vector();
    fem::QuasiStaticSolver solver(op, test::quiet_newton(), {.steps = 2});
    solver.solve(u.get());
    const VectorX uh = op.space().gather_all(u.get());
    const Points<3>& x = op.space().dofs().dof_points();
    double worst = 0;
    for (Index d = 0; d < x.rows(); ++d)
      worst = std::max(worst, (uh.segment<3>(3 * d) - affine(x.row(d).transpose())).cwiseAbs().maxCoeff());
    EXPECT_LT(worst, 1e-9) << (order == 1 ? "Q1" : "P2") << ": max nodal error";
    RecordProperty(order == 1 ? "q1_max_nodal_error" : "p2_max_nodal_error", sci(worst));
    EXPECT_NEAR(op.min_det_F(u.get()), G.determinant(), 1e-9);
  }
}

// A cantilever of square section clamped at x = 0 under a small transverse end
// load P: the tip deflection is Timoshenko's P L³/(3EI) + P L/(κGA) up to the
// local clamping effect (a few per cent at L/h = 6), and neo-Hookean equals
// linear elasticity in the small-load limit.
TEST(QuasiStatic3d, SmallLoadCantileverMatchesBeamTheory) {
  const double L = 6, E = 1000, nu = 0.3, P = 1e-3;
  const Mesh<3> mesh = test::box_mesh(Point<3>(L, 1, 1), {12, 2, 2}, CellType::hexahedron);
  std::array<double, 2> tip{};
  for (const MaterialModel model : {MaterialModel::neo_hookean, MaterialModel::linear_elastic}) {
    fem::ElasticityData<3> data = test::clamped_at_x0(model, E, nu);
    data.neumann.push_back({{1}, [&](const Point<3>&, double) { return Point<3>(0, 0, -P); }});
    const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::identity_map_3d(), 2, 0, data);
    petsc::Vector u = op.space().create_vector();
    fem::QuasiStaticSolver solver(op, test::quiet_newton());
    solver.solve(u.get());
    // Mean vertical displacement of the end face's nodes.
    const VectorX uh = op.space().gather_all(u.get());
    const Points<3>& x = op.space().dofs().dof_points();
    double sum = 0;
    int count = 0;
    for (Index d = 0; d < x.rows(); ++d)
      if (std::abs(x(d, 0) - L) < 1e-12) {
        sum += uh(3 * d + 2);
        ++count;
      }
    tip[model == MaterialModel::linear_elastic] = -sum / count;
  }
  const double I = 1.0 / 12, G = E / (2 * (1 + nu)), kappa = 10 * (1 + nu) / (12 + 11 * nu);
  const double timoshenko = P * L * L * L / (3 * E * I) + P * L / (kappa * G);
  EXPECT_NEAR(tip[1], timoshenko, 0.03 * timoshenko)
      << "linear FE " << tip[1] << ", beam theory " << timoshenko;
  EXPECT_NEAR(tip[0], tip[1], 1e-4 * tip[1]) << "neo-Hookean vs linear elasticity";
  RecordProperty("tip_linear", sci(tip[1]));
  RecordProperty("tip_neo_hookean", sci(tip[0]));
  RecordProperty("tip_timoshenko", sci(timoshenko));
}

TEST(QuasiStatic3d, NewtonConvergesQuadraticallyUnderAModerateLoad) {
  const Mesh<3> mesh = test::box_mesh(Point<3>(2, 1, 1), {4, 2, 2}, CellType::tetrahedron);
  fem::ElasticityData<3> data = test::clamped_at_x0(MaterialModel::neo_hookean);
  data.neumann.push_back({{1}, [](const Point<3>&, double) { return Point<3>(0, 0.1, -0.3); }});
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, std::make_shared<test::WarpedBoxMap>(), 2, 0, data);
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, test::quiet_newton(), {.steps = 1});
  const auto report = solver.solve(u.get());
  ASSERT_EQ(report.steps.size(), 1u);
  const auto& r = report.steps[0].residuals;
  ASSERT_GE(r.size(), 4u) << "a moderate load should need several Newton iterations";
  EXPECT_LE(r.size(), 12u);
  int quadratic = 0;
  for (std::size_t k = 1; k + 1 < r.size(); ++k) {
    const double ek = r[k] / r[0], ek1 = r[k + 1] / r[0];
    if (ek < 5e-2 && ek1 > 5e-12) {  // below ~1e-12 |R_0| the residual is at round-off level
      EXPECT_LE(ek1, 10 * ek * ek) << "iteration " << k << ": " << r[k] << " -> " << r[k + 1];
      ++quadratic;
    }
  }
  EXPECT_GE(quadratic, 1);
  RecordProperty("newton_residuals", [&] {
    std::string s;
    for (double x : r) s += sci(x) + " ";
    return s;
  }());
}

namespace {

struct EnergyRun {
  std::vector<double> energy;
  fem::TransientReport report;
};

/// A warped box clamped at x = 0, released with a transverse velocity growing away from the clamp.
EnergyRun swinging_box(MaterialModel model, double rho_infinity, int steps) {
  const Mesh<3> mesh = test::box_mesh(Point<3>(1, 1, 1), {2, 1, 1}, CellType::hexahedron);
  const fem::ElasticityData<3> data = test::clamped_at_x0(model);
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, std::make_shared<test::WarpedBoxMap>(), 2, 0, data);
  petsc::Vector u = op.space().create_vector(), v = op.space().create_vector();
  Points<3> x;
  op.map().eval(op.space().dofs().dof_points(), x);
  for (Index d = 0; d < op.space().dofs().num_dofs(); ++d) {
    const PetscInt row = op.space().global(d, 2);
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
  fem::NewtonOptions newton = test::quiet_newton();
  newton.rtol = 1e-13;
  newton.atol = 1e-14;
  fem::TransientSolver solver(op, options, newton);
  EnergyRun run;
  run.report = solver.solve(u.get(), v.get(), [&](const fem::TransientStep& s, Vec, Vec) {
    run.energy.push_back(s.total_energy());
  });
  return run;
}

}  // namespace

TEST(Transient3d, UndampedGeneralizedAlphaConservesEnergyOfLinearElasticity) {
  const EnergyRun run = swinging_box(MaterialModel::linear_elastic, 1.0, 30);
  ASSERT_EQ(run.energy.size(), 31u) << "step 0 and 30 steps";
  EXPECT_EQ(run.report.steps, 30);
  const double e0 = run.energy.front();
  ASSERT_GT(e0, 0);
  double drift = 0;
  for (double e : run.energy) drift = std::max(drift, std::abs(e - e0) / e0);
  EXPECT_LT(drift, 1e-8) << "max relative energy drift over 30 steps";
}

TEST(Transient3d, DissipatesWithRhoInfinityBelowOneAndStaysBoundedForNeoHookean) {
  const EnergyRun damped = swinging_box(MaterialModel::linear_elastic, 0.3, 30);
  EXPECT_LT(damped.energy.back(), damped.energy.front() * (1 - 1e-4)) << "ρ∞ < 1 must dissipate energy";
  const EnergyRun nh = swinging_box(MaterialModel::neo_hookean, 1.0, 20);
  const double e0 = nh.energy.front();
  for (double e : nh.energy) EXPECT_NEAR(e, e0, 0.02 * e0);
}
