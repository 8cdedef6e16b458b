// Geometric multigrid for 3D elasticity (block size 3, Galerkin coarse
// operators of every Newton Jacobian): a neo-Hookean box compressed and
// twisted on a warped map, solved by Newton with GMRES + multigrid on
// hierarchies of three successive depths. The Krylov iterations per Newton step stay
// bounded as the mesh is refined, and the solution is the one Newton with
// MUMPS LU gives. Plus the rigid-body near-null space: built from the warped
// node positions, its modes are in the kernel of the small-strain stiffness.

#include <gtest/gtest.h>
#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "core/petsc/check.hpp"
#include "elasticity_3d_fixtures.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/elasticity/near_null_space.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "multigrid/geometric_multigrid.hpp"

using namespace warpfem;
using fem::MaterialModel;
using warpfem::CellType;

namespace {

constexpr double kLength = 2.0;

/// Clamped at x = 0; the end face x0 = 2 pushed in by 0.1 and turned by 15°
/// about the bar's axis (y = z = 0.5), prescribed at the warped node positions.
fem::ElasticityData<3> compressed_twisted_bar() {
  fem::ElasticityData<3> data = test::clamped_at_x0(MaterialModel::neo_hookean, 10.0, 0.3);
  const double angle = 15.0 * std::numbers::pi / 180.0, c = std::cos(angle), s = std::sin(angle);
  const fem::ComponentFunction<3> push = [](const Point<3>&, double) { return -0.1; };
  const fem::ComponentFunction<3> uy = [c, s](const Point<3>& x, double) {
    return c * (x.y() - 0.5) - s * (x.z() - 0.5) - (x.y() - 0.5);
  };
  const fem::ComponentFunction<3> uz = [c, s](const Point<3>& x, double) {
    return s * (x.y() - 0.5) + c * (x.z() - 0.5) - (x.z() - 0.5);
  };
  data.dirichlet.push_back({{1}, {push, uy, uz}});
  data.gravity = Point<3>(0, 0, -0.5);
  return data;
}

struct NewtonRun {
  VectorX u;
  std::vector<int> linear_iterations;  ///< of every Newton step of every load step
  int newton_iterations = 0;
};

/// Newton on the finest level of a hierarchy of `refinements` + 1 levels, with MUMPS LU
/// (`multigrid` false) or GMRES preconditioned by GeometricMultigrid<3> (Galerkin levels).
NewtonRun solve(MPI_Comm comm, CellType type, int order, int refinements, bool multigrid) {
  const fem::MeshHierarchy<3> hierarchy(test::box_mesh(Point<3>(kLength, 1, 1), {2, 1, 1}, type),
                                        refinements);
  const fem::HyperelasticOperator op(comm, hierarchy.finest(), std::make_shared<test::WarpedBoxMap>(), order,
                                     0, compressed_twisted_bar());
  fem::NewtonOptions newton = test::quiet_newton();
  newton.rtol = 1e-10;
  std::unique_ptr<multigrid::GeometricMultigrid<3>> mg;
  if (multigrid) {
    mg = std::make_unique<multigrid::GeometricMultigrid<3>>(hierarchy, op);
    EXPECT_EQ(mg->components(), 3);
    EXPECT_EQ(mg->num_levels(), refinements + 1);
    newton.ksp_type = "gmres";
    newton.configure_preconditioner = [&mg](KSP ksp, Mat jacobian) {
      WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp, 1e-10, 1e-50, PETSC_DEFAULT, 200));
      mg->configure(ksp, {jacobian});
    };
  }
  petsc::Vector u = op.space().create_vector();
  fem::QuasiStaticSolver solver(op, newton, {.steps = 1});
  const fem::QuasiStaticReport report = solver.solve(u.get());
  NewtonRun run{op.space().gather_all(u.get()), {}, report.newton_iterations()};
  for (const fem::LoadStep& step : report.steps)
    run.linear_iterations.insert(run.linear_iterations.end(), step.linear_iterations.begin(),
                                 step.linear_iterations.end());
  EXPECT_GT(op.min_det_F(u.get()), 0.3);
  return run;
}

struct Case {
  CellType type;
  int order;
  /// Hierarchies of first + 1, first + 2 and first + 3 levels (level 0: 2 x 1 x 1 cells).
  int first_refinements;
  /// Most GMRES iterations per Newton step may grow by this much over the three depths. P1 on
  /// tetrahedra is still approaching its plateau on these small meshes (+4, then +2).
  int spread;
};

std::string name(const ::testing::TestParamInfo<Case>& info) {
  return to_string(info.param.type) + "_order" + std::to_string(info.param.order);
}

class ElasticityMultigrid3d : public ::testing::TestWithParam<Case> {};

TEST_P(ElasticityMultigrid3d, NewtonMatchesLuWithBoundedKrylovIterations) {
  const Case& c = GetParam();
  std::vector<int> most;  // per depth: most GMRES iterations of a Newton step
  for (int refinements = c.first_refinements; refinements < c.first_refinements + 3; ++refinements) {
    const NewtonRun mg = solve(PETSC_COMM_WORLD, c.type, c.order, refinements, true);
    ASSERT_FALSE(mg.linear_iterations.empty());
    ASSERT_EQ(static_cast<int>(mg.linear_iterations.size()), mg.newton_iterations);
    const auto [lo, hi] = std::minmax_element(mg.linear_iterations.begin(), mg.linear_iterations.end());
    std::printf("[ %s%d, %d levels, %d DOFs ] GMRES iterations per Newton step %d..%d (%d Newton steps)\n",
                c.type == CellType::hexahedron ? "Q" : "P", c.order, refinements + 1,
                static_cast<int>(mg.u.size()), *lo, *hi, mg.newton_iterations);
    most.push_back(*hi);
    if (refinements != c.first_refinements) continue;
    const NewtonRun lu = solve(PETSC_COMM_WORLD, c.type, c.order, refinements, false);
    const double difference = (mg.u - lu.u).norm() / lu.u.norm();
    std::printf("    |u_mg - u_lu| / |u_lu| = %.1e (LU: %d Newton steps)\n", difference,
                lu.newton_iterations);
    EXPECT_LT(difference, 1e-8);
    EXPECT_LE(std::abs(mg.newton_iterations - lu.newton_iterations), 1) << "multigrid changed Newton's path";
  }
  // Bounded: a small spread over the depths, growth that does not accelerate.
  const auto [fewest, largest] = std::minmax_element(most.begin(), most.end());
  EXPECT_LE(*largest, 30);
  EXPECT_LE(*largest - *fewest, c.spread) << "the GMRES iterations per Newton step grow with refinement";
  EXPECT_LE(most[2] - most[1], std::max(most[1] - most[0], 1)) << "the growth accelerates";
}

INSTANTIATE_TEST_SUITE_P(Elements, ElasticityMultigrid3d,
                         ::testing::Values(Case{CellType::hexahedron, 1, 2, 3},
                                           Case{CellType::tetrahedron, 1, 2, 6},
                                           Case{CellType::hexahedron, 2, 1, 3},
                                           Case{CellType::tetrahedron, 2, 1, 3}),
                         name);

/// A shear that is not a similarity: rotations of x0 are not rigid in f(Ω0).
class ShearMap final : public mapping::Map<3> {
 public:
  void eval(const Points<3>& x0, Points<3>& x) const override {
    x.resize(x0.rows(), 3);
    for (Index p = 0; p < x0.rows(); ++p)
      x.row(p) << x0(p, 0) + 0.4 * x0(p, 1), 0.8 * x0(p, 1) + 0.3 * x0(p, 2), 1.2 * x0(p, 2) + 0.1;
  }
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override {
    J.resize(x0.rows(), 9);
    for (Index p = 0; p < x0.rows(); ++p) J.row(p) << 1, 0.4, 0, 0, 0.8, 0.3, 0, 0, 1.2;
  }
  std::string describe() const override { return "shear (test)"; }
};

/// max over the near-null-space modes of ‖K r‖ / (‖K‖_F ‖r‖), K the stiffness at u = 0 without
/// boundary conditions, the modes built from the node positions `modes_map` gives.
double worst_mode_residual(CellType type, int order, int cells, mapping::MapPtr<3> map,
                           const mapping::Map<3>& modes_map) {
  const Mesh<3> mesh = test::box_mesh(Point<3>(kLength, 1, 1), {2 * cells, cells, cells}, type);
  fem::ElasticityData<3> data;
  data.material = fem::Material::from_young_poisson(MaterialModel::neo_hookean, 10.0, 0.3);
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, mesh, map, order, 0, data);
  petsc::Matrix K = op.space().create_matrix();
  petsc::Vector u = op.space().create_vector(), Kr = op.space().create_vector();
  op.jacobian(u.get(), 0.0, K.get(), false);  // at u = 0: the small-strain stiffness
  fem::set_rigid_body_near_null_space(K.get(), op.space(), modes_map);
  MatNullSpace modes = nullptr;
  WARPFEM_PETSC_CHECK(MatGetNearNullSpace(K.get(), &modes));
  EXPECT_NE(modes, nullptr);
  PetscBool has_constant = PETSC_FALSE;
  PetscInt n = 0;
  const Vec* vecs = nullptr;
  WARPFEM_PETSC_CHECK(MatNullSpaceGetVecs(modes, &has_constant, &n, &vecs));
  EXPECT_EQ(n, 6);
  PetscReal k_norm = 0;
  WARPFEM_PETSC_CHECK(MatNorm(K.get(), NORM_FROBENIUS, &k_norm));
  double worst = 0;
  for (PetscInt i = 0; i < n; ++i) {
    PetscReal r_norm = 0, kr_norm = 0;
    WARPFEM_PETSC_CHECK(MatMult(K.get(), vecs[i], Kr.get()));
    WARPFEM_PETSC_CHECK(VecNorm(vecs[i], NORM_2, &r_norm));
    WARPFEM_PETSC_CHECK(VecNorm(Kr.get(), NORM_2, &kr_norm));
    worst = std::max(worst, kr_norm / (k_norm * r_norm));
  }
  return worst;
}

class RigidBodyModes : public ::testing::TestWithParam<std::tuple<CellType, int>> {};

TEST_P(RigidBodyModes, AreRigidInTheWarpedDomain) {
  const auto [type, order] = GetParam();
  const mapping::IdentityMap<3> unwarped;
  // An affine non-similar map: the modes about f(x0) are exact, those about x0 are not.
  const auto shear = std::make_shared<ShearMap>();
  const double affine = worst_mode_residual(type, order, 2, shear, *shear);
  const double affine_x0 = worst_mode_residual(type, order, 2, shear, unwarped);
  EXPECT_LT(affine, 1e-12);
  EXPECT_GT(affine_x0, 1e-3);
  // A curved map: the modes about f(x0) are rigid up to the interpolation error of f, which
  // vanishes under refinement (and is zero for P2/Q2: this f is quadratic); those about x0
  // stay far from the kernel.
  const auto warp = std::make_shared<test::WarpedBoxMap>();
  const double coarse = worst_mode_residual(type, order, 1, warp, *warp);
  const double fine = worst_mode_residual(type, order, 2, warp, *warp);
  const double fine_x0 = worst_mode_residual(type, order, 2, warp, unwarped);
  std::printf("[ %s%d ] shear: %.1e (x0: %.1e); warped: h %.1e, h/2 %.1e (x0: %.1e)\n",
              type == CellType::hexahedron ? "Q" : "P", order, affine, affine_x0, coarse, fine, fine_x0);
  if (order == 1)
    EXPECT_LT(fine, 0.6 * coarse);
  else
    EXPECT_LT(fine, 1e-12);
  EXPECT_LT(fine, 0.1 * fine_x0);
}

INSTANTIATE_TEST_SUITE_P(Elements, RigidBodyModes,
                         ::testing::Values(std::make_tuple(CellType::hexahedron, 1),
                                           std::make_tuple(CellType::tetrahedron, 1),
                                           std::make_tuple(CellType::hexahedron, 2),
                                           std::make_tuple(CellType::tetrahedron, 2)));

}  // namespace
