// The assembled operator: consistent Jacobian, linear limit, convergence under refinement.

#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "elasticity_fixtures.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"

using namespace warpfem;
using fem::MaterialModel;
using warpfem::CellType;

namespace {

fem::ElasticityData<2> clamped_left(MaterialModel model) {
  fem::ElasticityData<2> data;
  data.material = fem::Material::from_young_poisson(model, 10.0, 0.3, 1.0);
  const fem::ScalarFunction<2> zero = [](const Point<2>&, double) { return 0.0; };
  data.dirichlet.push_back({{3}, {zero, zero}});
  return data;
}

fem::NewtonOptions quiet_newton() {
  fem::NewtonOptions o;
  o.log_iterations = false;
  o.rtol = 1e-12;
  o.atol = 1e-13;
  return o;
}

struct OperatorCase {
  CellType type;
  int order;
  const char* name;
};

class OperatorJacobian : public ::testing::TestWithParam<OperatorCase> {};

}  // namespace

TEST_P(OperatorJacobian, MatchesFiniteDifferencesOfTheResidualOnAWarpedMesh) {
  const auto& param = GetParam();
  const warpfem::Mesh<2> mesh = test::block_mesh(1, 1, 3, 3, param.type);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::neo_hookean);
  data.gravity = Point<2>(0, -2);
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::warped_square_map(), param.order, 0, data);
  const auto& space = op.space();
  petsc::Vector u = space.create_vector(), du = space.create_vector(), up = space.create_vector(),
                um = space.create_vector(), rp = space.create_vector(), rm = space.create_vector(),
                jdu = space.create_vector();
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> dist(-1, 1);
  PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArray(u.get(), &a));
  for (PetscInt i = 0; i < space.num_owned(); ++i) a[i] = 0.01 * dist(gen);
  WARPFEM_PETSC_CHECK(VecRestoreArray(u.get(), &a));
  WARPFEM_PETSC_CHECK(VecGetArray(du.get(), &a));
  for (PetscInt i = 0; i < space.num_owned(); ++i) a[i] = dist(gen);
  WARPFEM_PETSC_CHECK(VecRestoreArray(du.get(), &a));
  op.zero_constrained(du.get());  // the constrained rows are the identity on both sides
  ASSERT_GT(op.min_det_F(u.get()), 0.5);

  petsc::Matrix J = space.create_matrix();
  op.jacobian(u.get(), 0.0, J.get());
  WARPFEM_PETSC_CHECK(MatMult(J.get(), du.get(), jdu.get()));
  const double h = 1e-6;
  WARPFEM_PETSC_CHECK(VecWAXPY(up.get(), h, du.get(), u.get()));
  WARPFEM_PETSC_CHECK(VecWAXPY(um.get(), -h, du.get(), u.get()));
  ASSERT_TRUE(op.residual(up.get(), nullptr, 1.0, 0.0, rp.get()));
  ASSERT_TRUE(op.residual(um.get(), nullptr, 1.0, 0.0, rm.get()));
  const VectorX fd = (test::to_eigen(space, rp.get()) - test::to_eigen(space, rm.get())) / (2 * h);
  const VectorX exact = test::to_eigen(space, jdu.get());
  const double rel = (fd - exact).norm() / exact.norm();
  EXPECT_LE(rel, 1e-6) << param.name << ": relative difference " << rel;
}

INSTANTIATE_TEST_SUITE_P(Elements, OperatorJacobian,
                         ::testing::Values(OperatorCase{CellType::triangle, 1, "P1"},
                                           OperatorCase{CellType::triangle, 2, "P2"},
                                           OperatorCase{CellType::quadrilateral, 1, "Q1"},
                                           OperatorCase{CellType::quadrilateral, 2, "Q2"}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(HyperelasticOperator, MassShiftAddsTheConsistentMassMatrix) {
  const warpfem::Mesh<2> mesh = test::block_mesh(2, 1, 4, 2, CellType::triangle);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::linear_elastic);
  data.dirichlet.clear();
  data.material.density = 3.0;
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::identity_map(), 2, 0, data);
  petsc::Vector u = op.space().create_vector(), ones = op.space().create_vector(),
                r = op.space().create_vector(), m1 = op.space().create_vector();
  petsc::Matrix K = op.space().create_matrix(), KM = op.space().create_matrix();
  op.jacobian(u.get(), 0.0, K.get());
  op.jacobian(u.get(), 1.0, KM.get());
  WARPFEM_PETSC_CHECK(VecSet(ones.get(), 1.0));
  WARPFEM_PETSC_CHECK(MatAXPY(KM.get(), -1.0, K.get(), SAME_NONZERO_PATTERN));
  WARPFEM_PETSC_CHECK(MatMult(KM.get(), ones.get(), m1.get()));
  PetscScalar total = 0;
  WARPFEM_PETSC_CHECK(VecSum(m1.get(), &total));
  EXPECT_NEAR(total, 2 * 3.0 * 2.0, 1e-10) << "1ᵀ M 1 = components x density x area";
  // The residual with inertia a = 1 is M·1 (rigid translation has no internal force).
  ASSERT_TRUE(op.residual(ones.get(), ones.get(), 0.0, 0.0, r.get()));
  WARPFEM_PETSC_CHECK(VecAXPY(r.get(), -1.0, m1.get()));
  PetscReal norm = 0;
  WARPFEM_PETSC_CHECK(VecNorm(r.get(), NORM_INFINITY, &norm));
  EXPECT_LT(norm, 1e-12);
}

TEST(QuasiStatic, SmallLoadLimitEqualsLinearElasticity) {
  const warpfem::Mesh<2> mesh = test::block_mesh(4, 1, 8, 2, CellType::quadrilateral);
  std::array<VectorX, 2> solutions;
  for (const MaterialModel model : {MaterialModel::neo_hookean, MaterialModel::linear_elastic}) {
    fem::ElasticityData<2> data = clamped_left(model);
    data.neumann.push_back({{1}, [](const Point<2>&, double) { return Point<2>(0.0, -1e-5); }});
    const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::identity_map(), 2, 0, data);
    petsc::Vector u = op.space().create_vector();
    fem::QuasiStaticSolver solver(op, quiet_newton());
    solver.solve(u.get());
    solutions[model == MaterialModel::linear_elastic] = test::to_eigen(op.space(), u.get());
  }
  const double rel = (solutions[0] - solutions[1]).norm() / solutions[1].norm();
  EXPECT_GT(solutions[1].norm(), 0);
  EXPECT_LT(rel, 1e-4) << "neo-Hookean and linear elasticity differ at O(load)";
}

TEST(QuasiStatic, NewtonConvergesQuadraticallyUnderAModerateLoad) {
  const warpfem::Mesh<2> mesh = test::block_mesh(4, 1, 8, 2, CellType::triangle, 1);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::neo_hookean);
  data.neumann.push_back({{1}, [](const Point<2>&, double) { return Point<2>(0.0, -0.02); }});
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::warped_square_map(), 1, 0, data);
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, quiet_newton(), {.steps = 1});
  const auto report = solver.solve(u.get());
  ASSERT_EQ(report.steps.size(), 1u);
  const auto& r = report.steps[0].residuals;
  ASSERT_GE(r.size(), 4u) << "a moderate load should need several Newton iterations";
  EXPECT_LE(r.size(), 12u);
  // In the asymptotic range e_{k+1} <= C e_k^2 (normalized by the initial residual).
  int quadratic = 0;
  for (std::size_t k = 1; k + 1 < r.size(); ++k) {
    const double ek = r[k] / r[0], ek1 = r[k + 1] / r[0];
    if (ek < 5e-2 && ek1 > 5e-12) {  // below ~1e-12 |R_0| the residual is at round-off level
      EXPECT_LE(ek1, 10 * ek * ek) << "iteration " << k << ": " << r[k] << " -> " << r[k + 1];
      ++quadratic;
    }
  }
  EXPECT_GE(quadratic, 1);
}

TEST(QuasiStatic, InvertingTrialStatesAreRejectedAndTheLoadStepIsCut) {
  // A compressive traction of 1.5 E: the first (linear) Newton step inverts elements.
  const warpfem::Mesh<2> mesh = test::block_mesh(1, 1, 4, 4, CellType::triangle);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::neo_hookean);
  data.neumann.push_back({{1}, [](const Point<2>&, double) { return Point<2>(-15.0, 0.0); }});
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::identity_map(), 1, 0, data);
  fem::NewtonOptions newton = quiet_newton();
  newton.rtol = 1e-9;
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, newton, {.steps = 1, .min_increment = 1e-4});
  const auto report = solver.solve(u.get());
  EXPECT_GT(report.domain_rejections, 0) << "inverted trial states must have been seen and rejected";
  EXPECT_NEAR(report.steps.back().load, 1.0, 1e-14);
  PetscReal norm = 0;
  WARPFEM_PETSC_CHECK(VecNorm(u.get(), NORM_2, &norm));
  EXPECT_TRUE(std::isfinite(norm));
  EXPECT_GT(op.min_det_F(u.get()), 0.0);
}

TEST(QuasiStatic, FailureBelowTheMinimumIncrementIsAClearError) {
  // No Dirichlet condition: the stiffness is singular, Newton cannot converge.
  const warpfem::Mesh<2> mesh = test::block_mesh(1, 1, 2, 2, CellType::triangle);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::neo_hookean);
  data.dirichlet.clear();
  data.gravity = Point<2>(0, -1);
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::identity_map(), 1, 0, data);
  fem::NewtonOptions newton = quiet_newton();
  newton.max_iterations = 3;
  newton.factor_solver = "petsc";
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, newton, {.steps = 1, .min_increment = 0.2});
  try {
    solver.solve(u.get());
    FAIL() << "expected warpfem::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("quasi-static solve failed"), std::string::npos) << e.what();
    EXPECT_FALSE(e.context().hint.empty());
  }
  PetscReal norm = 0;
  WARPFEM_PETSC_CHECK(VecNorm(u.get(), NORM_2, &norm));
  EXPECT_EQ(norm, 0.0) << "the last converged state (s = 0) is kept";
}

namespace {

/// Exact displacement of the manufactured solution and its gradient.
Point<2> u_exact(const Point<2>& x) {
  return Point<2>(0.1 * std::sin(x.x()) * x.y(), 0.05 * std::cos(x.y()) * x.x() * x.x());
}
Matrix<2> grad_u_exact(const Point<2>& x) {
  Matrix<2> H;
  H << 0.1 * std::cos(x.x()) * x.y(), 0.1 * std::sin(x.x()), 0.1 * std::cos(x.y()) * x.x(),
      -0.05 * std::sin(x.y()) * x.x() * x.x();
  return H;
}

double convergence_error(const warpfem::Mesh<2>& mesh, int order, bool warped,
                         const fem::Material& material) {
  fem::ElasticityData<2> data;
  data.material = material;
  // b = -Div P(I + ∇u_exact), by central differences of the analytic P.
  data.body_force = [material](const Point<2>& x, double) {
    Point<2> b = Point<2>::Zero();
    const double h = 1e-4;
    for (int J = 0; J < 2; ++J) {
      Point<2> xp = x, xm = x;
      xp(J) += h;
      xm(J) -= h;
      const Matrix<2> Pp = material.first_piola<2>(Matrix<2>(Matrix<2>::Identity() + grad_u_exact(xp)));
      const Matrix<2> Pm = material.first_piola<2>(Matrix<2>(Matrix<2>::Identity() + grad_u_exact(xm)));
      b -= (Pp.col(J) - Pm.col(J)) / (2 * h);
    }
    return b;
  };
  const fem::ScalarFunction<2> ux = [](const Point<2>& x, double) { return u_exact(x).x(); };
  const fem::ScalarFunction<2> uy = [](const Point<2>& x, double) { return u_exact(x).y(); };
  data.dirichlet.push_back({{}, {ux, uy}});
  const fem::HyperelasticOperator op(
      MPI_COMM_SELF, mesh, warped ? test::warped_square_map() : test::identity_map(), order, 0, data);
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, quiet_newton(), {.steps = 1});
  solver.solve(u.get());
  return test::l2_error(op, u.get(), [](const Point<2>& x, double) { return u_exact(x); });
}

}  // namespace

// Nonlinear manufactured solution, Dirichlet data on the whole boundary, observed L2 rates.
// Order 1 runs on a warped mesh (mean value map of the square onto a quadrilateral). Order 2
// runs unwarped: mean value coordinates are not smooth at the polygon's corners, which limits
// P2/Q2 on that map to an observed rate of about 2.2 (the map's Jacobian itself is exact).
TEST(QuasiStatic, ManufacturedSolutionConvergesAtTheOptimalRate) {
  const fem::Material material = fem::Material::from_young_poisson(MaterialModel::neo_hookean, 10.0, 0.3);
  for (const auto& [type, order, warped, expected] :
       {std::tuple{CellType::triangle, 1, true, 2.0}, std::tuple{CellType::quadrilateral, 1, true, 2.0},
        std::tuple{CellType::triangle, 2, false, 3.0}, std::tuple{CellType::quadrilateral, 2, false, 3.0}}) {
    std::vector<double> errors;
    for (int level = 0; level < 3; ++level)
      errors.push_back(
          convergence_error(test::block_mesh(1, 1, 2, 2, type, level + 1), order, warped, material));
    for (std::size_t k = 1; k < errors.size(); ++k) {
      const double rate = std::log2(errors[k - 1] / errors[k]);
      std::printf("%s order %d level %zu: L2 error %.3e, rate %.2f\n", warpfem::to_string(type).c_str(),
                  order, k, errors[k], rate);
      if (k + 1 == errors.size()) {
        EXPECT_NEAR(rate, expected, 0.25);
      }
    }
  }
}

TEST(VectorSpace, BlockMatrixTypesAssembleTheSameOperator) {
  const warpfem::Mesh<2> mesh = test::block_mesh(1, 1, 3, 2, CellType::quadrilateral);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::neo_hookean);
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::warped_square_map(), 2, 0, data);
  WARPFEM_PETSC_CHECK(PetscOptionsSetValue(nullptr, "-vector_space_test_mat_type", "baij"));
  petsc::Matrix aij = op.space().create_matrix(), baij = op.space().create_matrix("vector_space_test_");
  WARPFEM_PETSC_CHECK(PetscOptionsClearValue(nullptr, "-vector_space_test_mat_type"));
  PetscBool is_baij = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(baij.get()), &is_baij,
                                                MATSEQBAIJ, MATMPIBAIJ, ""));
  ASSERT_TRUE(is_baij);
  PetscInt bs = 0;
  WARPFEM_PETSC_CHECK(MatGetBlockSize(aij.get(), &bs));
  EXPECT_EQ(bs, 2);
  petsc::Vector u = op.space().create_vector(), x = op.space().create_vector(),
                y1 = op.space().create_vector(), y2 = op.space().create_vector();
  WARPFEM_PETSC_CHECK(VecSet(u.get(), 0.01));
  WARPFEM_PETSC_CHECK(VecSet(x.get(), 1.0));
  op.jacobian(u.get(), 2.0, aij.get());
  op.jacobian(u.get(), 2.0, baij.get());
  WARPFEM_PETSC_CHECK(MatMult(aij.get(), x.get(), y1.get()));
  WARPFEM_PETSC_CHECK(MatMult(baij.get(), x.get(), y2.get()));
  const VectorX a = test::to_eigen(op.space(), y1.get()), b = test::to_eigen(op.space(), y2.get());
  EXPECT_LT((a - b).norm(), 1e-12 * a.norm());
}

namespace {

/// The moderate-load cantilever of NewtonConvergesQuadraticallyUnderAModerateLoad with
/// tolerances that only the exact solution meets: the residual stalls at round-off level.
fem::QuasiStaticReport solve_to_round_off(double step_tolerance) {
  static const warpfem::Mesh<2> mesh = test::block_mesh(4, 1, 8, 2, CellType::triangle, 1);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::neo_hookean);
  data.neumann.push_back({{1}, [](const Point<2>&, double) { return Point<2>(0.0, -0.02); }});
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::warped_square_map(), 1, 0, data);
  fem::NewtonOptions newton = quiet_newton();
  newton.rtol = 0;
  newton.atol = 1e-300;
  newton.step_tolerance = step_tolerance;
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, newton, {.steps = 1, .min_increment = 0.5});
  fem::QuasiStaticReport report = solver.solve(u.get());
  petsc::Vector r = op.space().create_vector();
  EXPECT_TRUE(op.residual(u.get(), nullptr, 1.0, 0.0, r.get()));
  PetscReal norm = 0;
  WARPFEM_PETSC_CHECK(VecNorm(r.get(), NORM_2, &norm));
  EXPECT_LT(norm, 1e-10 * report.steps.front().residuals.front()) << "converged to round-off level";
  return report;
}

}  // namespace

TEST(QuasiStatic, NewtonStopsAtTheResidualsRoundOffFloor) {
  // rtol |R_0| and atol below what floating point can reach (after a good predictor |R_0| is
  // small, and the floor grows with the problem size): the full Newton correction falls below
  // step_tolerance |u| and the solve converges instead of failing the load step.
  const fem::QuasiStaticReport report = solve_to_round_off(1e-10);
  ASSERT_EQ(report.steps.size(), 1u);
  EXPECT_EQ(report.rejected_steps, 0);
  EXPECT_LE(report.steps[0].iterations, 12);
  const auto& r = report.steps[0].residuals;
  EXPECT_GT(r.back(), 0.0) << "the residual never reaches 0: only the step test can end the solve";
}

TEST(QuasiStatic, WithoutTheStepTestTheRoundOffFloorFailsTheLoadStep) {
  // The mechanism above: with step_tolerance 0 the same solve cannot meet its tolerances.
  EXPECT_THROW(solve_to_round_off(0.0), Error);
}

TEST(HyperelasticOperator, SampledDetFSeesACellFoldedBetweenItsQuadraturePoints) {
  // u = (c x y, 0) on one Q2 cell: det F = 1 + c y is -0.05 along y = 1 but positive at every
  // quadrature point (the highest one lies at y ≈ 0.93), so the residual accepts the folded cell.
  const warpfem::Mesh<2> mesh = test::block_mesh(1, 1, 1, 1, CellType::quadrilateral);
  fem::ElasticityData<2> data = clamped_left(MaterialModel::neo_hookean);
  data.dirichlet.clear();
  const fem::HyperelasticOperator op(MPI_COMM_SELF, mesh, test::identity_map(), 2, 0, data);
  const double c = -1.05;
  petsc::Vector u = op.space().create_vector(), r = op.space().create_vector();
  const auto& x = op.space().dofs().dof_points();
  for (Index d = 0; d < x.rows(); ++d)
    WARPFEM_PETSC_CHECK(VecSetValue(u.get(), op.space().global(d, 0), c * x(d, 0) * x(d, 1), INSERT_VALUES));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(u.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(u.get()));
  const double at_points = op.min_det_F(u.get());
  EXPECT_GT(at_points, 0.0);
  EXPECT_TRUE(op.residual(u.get(), nullptr, 0.0, 0.0, r.get()));
  const auto fold = op.min_det_F_in_cells(u.get());
  EXPECT_NEAR(fold.min, 1 + c, 1e-6);
  EXPECT_NEAR(fold.x.y(), 1.0, 1e-6);
  EXPECT_NEAR(fold.cell_quadrature_min, at_points, 1e-14);
}

namespace {

/// The block of examples/block_compression.json (Q2, 8 x 8 cells, 2,178 DOFs) on a
/// trapezoid, clamped at the bottom and pushed down by `compression` at the top. The
/// operator keeps references to the mesh and the data, so the three live together
/// (constructed in place, never moved).
struct CompressedBlock {
  explicit CompressedBlock(double compression)
      : mesh(test::block_mesh(1, 1, 8, 8, CellType::quadrilateral, 1)) {
    mapping::MapSpec spec;
    spec.type = "barycentric";
    spec.source = test::rectangle(1, 1);
    spec.target =
        Polygon({Point<2>(0, 0), Point<2>(1.2, 0), Point<2>(1.0, 1.0), Point<2>(0.2, 1.0)}, "trapezoid");
    data.material = fem::Material::from_young_poisson(MaterialModel::neo_hookean, 1000.0, 0.3);
    data.boundary_polygon = spec.source;
    const fem::ScalarFunction<2> zero = [](const Point<2>&, double) { return 0.0; };
    const fem::ScalarFunction<2> down = [compression](const Point<2>&, double) { return -compression; };
    data.dirichlet.push_back({{0}, {zero, zero}});
    data.dirichlet.push_back({{2}, {zero, down}});
    op = std::make_unique<fem::HyperelasticOperator<2>>(MPI_COMM_SELF, mesh, mapping::make_map(spec), 2, 0,
                                                        data);
  }
  CompressedBlock(const CompressedBlock&) = delete;
  CompressedBlock& operator=(const CompressedBlock&) = delete;

  warpfem::Mesh<2> mesh;
  fem::ElasticityData<2> data;
  std::unique_ptr<fem::HyperelasticOperator<2>> op;
};

}  // namespace

TEST(QuasiStatic, ALoadBeyondACornerFoldStopsEarlyWithTheReason) {
  // The block of examples/block_compression.json (2,178 DOFs) compressed by 60 % in 16 steps:
  // near s = 0.7 the free surface folds over at a clamped corner, the equilibrium path loses
  // stability, and no smaller increment gets past. The solve stops after two attempts from the
  // last converged state, saying why, instead of halving down to the minimum increment.
  const CompressedBlock block(0.6);
  const fem::HyperelasticOperator<2>& op = *block.op;
  fem::NewtonOptions newton = quiet_newton();
  newton.rtol = 1e-10;
  newton.atol = 1e-12;
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, newton, {.steps = 16, .min_increment = 1e-4});
  double last = 0;
  try {
    solver.solve(u.get(), [&](const fem::LoadStep& step, Vec) { last = step.load; });
    FAIL() << "expected the solve to stop at the corner fold";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("loses stability"), std::string::npos) << what;
    EXPECT_NE(what.find("negative eigenvalue"), std::string::npos) << what;
    EXPECT_NE(what.find("folds between its quadrature points"), std::string::npos) << what;
    EXPECT_NE(e.context().hint.find("clamped"), std::string::npos);
  }
  EXPECT_GT(last, 0.5) << "the stable part of the path is followed";
  EXPECT_LT(last, 0.8);
  EXPECT_GT(op.min_det_F(u.get()), 0.0) << "u keeps the last converged state";
}

TEST(QuasiStatic, AnUnstableFinalEquilibriumIsReported) {
  // The block of examples/block_compression.json (2,178 DOFs) in 4 load steps: at 30 % the final
  // equilibrium is stable; at 55 % Newton still converges at s = 1, but onto an equilibrium past
  // the corner fold whose tangent has negative eigenvalues.
  for (const double compression : {0.3, 0.55}) {
    const CompressedBlock block(compression);
    const fem::HyperelasticOperator<2>& op = *block.op;
    petsc::Vector u = op.space().create_vector();
    fem::QuasiStaticSolver solver(op, quiet_newton(), {.steps = 4, .min_increment = 1e-3});
    const fem::QuasiStaticReport report = solver.solve(u.get());
    ASSERT_NEAR(report.steps.back().load, 1.0, 1e-14);
    if (report.final_negative_eigenvalues < 0) GTEST_SKIP() << "PETSc without MUMPS";
    if (compression < 0.5)
      EXPECT_EQ(report.final_negative_eigenvalues, 0);
    else
      EXPECT_GT(report.final_negative_eigenvalues, 0);
  }
}
