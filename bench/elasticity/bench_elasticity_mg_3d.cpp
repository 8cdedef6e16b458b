// 3D elasticity: geometric multigrid against algebraic multigrid on the same
// Newton Jacobians. A neo-Hookean box [0, 2] x [0, 1]² under a smooth warp,
// clamped at x0 = 0, its end x0 = 2 pushed in and twisted, is solved by Newton
// (GMRES + geometric multigrid to 1e-10), which records every linear system it
// solves (Jacobian and right-hand side, predictors included). Each system is
// then solved to a relative residual of 1e-8 by GMRES preconditioned with
//   gmg          GeometricMultigrid<3> (Galerkin coarse operators, the Newton default),
//   gamg         PETSc GAMG with the rigid-body near-null space about f(x0),
//   hypre        hypre BoomerAMG, PETSc's defaults (block size 3 passed on),
//   hypre-3d     BoomerAMG with the usual 3D settings: HMIS coarsening, ext+i interpolation
//                with at most 4 entries per row, strength threshold 0.5,
//   hypre-nodal  BoomerAMG with nodal coarsening (-pc_hypre_boomeramg_nodal_coarsen 6; the
//                rigid-body modes are attached, so ..._vec_interp_variant 1-3 can be tried),
// and with -lu also by MUMPS LU, in rounds whose order alternates; per method
// the median over rounds of the summed set-up and solve times, and the
// iterations per system.
//
//   bench_elasticity_mg_3d [-type hexahedron|tetrahedron] [-order 1|2] [-n 2] [-refinements 3] [-rounds 3]
//   [-lu]
//
// -n: level 0 has 2n x n x n cells; the finest 2^refinements times as many per side.
// Every method's KSP has its own prefix (gmg_, gamg_, hypre_, hypre_3d_, hypre_nodal_, lu_) for options.

#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_options.hpp"
#include "core/environment.hpp"
#include "core/log.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/elasticity/near_null_space.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "multigrid/geometric_multigrid.hpp"

using namespace warpfem;
using bench::int_option;
using bench::string_option;

namespace {

/// f(x) = x + (0.1 y z, 0.1 x², 0.05 x y): smooth, not affine.
class WarpedBox final : public mapping::Map<3> {
 public:
  void eval(const Points<3>& x0, Points<3>& x) const override {
    x.resize(x0.rows(), 3);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double a = x0(p, 0), b = x0(p, 1), c = x0(p, 2);
      x.row(p) << a + 0.1 * b * c, b + 0.1 * a * a, c + 0.05 * a * b;
    }
  }
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override {
    J.resize(x0.rows(), 9);
    for (Index p = 0; p < x0.rows(); ++p) {
      const double a = x0(p, 0), b = x0(p, 1), c = x0(p, 2);
      J.row(p) << 1, 0.1 * c, 0.1 * b, 0.2 * a, 1, 0, 0.05 * b, 0.05 * a, 1;
    }
  }
  std::string describe() const override { return "warped box"; }
};

fem::ElasticityData<3> compressed_twisted_bar() {
  fem::ElasticityData<3> data;
  data.material = fem::Material::from_young_poisson(fem::MaterialModel::neo_hookean, 10.0, 0.3);
  const fem::ComponentFunction<3> zero = [](const Point<3>&, double) { return 0.0; };
  data.dirichlet.push_back({{0}, {zero, zero, zero}});
  const double angle = 20.0 * std::numbers::pi / 180.0, c = std::cos(angle), s = std::sin(angle);
  const fem::ComponentFunction<3> push = [](const Point<3>&, double) { return -0.15; };
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

/// A linear system Newton solved: copies of its Jacobian and right-hand side.
struct System {
  petsc::Matrix J;
  petsc::Vector b;
};

PetscErrorCode record(KSP ksp, Vec b, Vec, void* ctx) {
  auto* systems = static_cast<std::vector<System>*>(ctx);
  Mat A = nullptr;
  WARPFEM_PETSC_CHECK(KSPGetOperators(ksp, &A, nullptr));
  System s;
  WARPFEM_PETSC_CHECK(MatDuplicate(A, MAT_COPY_VALUES, s.J.out()));
  WARPFEM_PETSC_CHECK(VecDuplicate(b, s.b.out()));
  WARPFEM_PETSC_CHECK(VecCopy(b, s.b.get()));
  systems->push_back(std::move(s));
  return 0;
}

struct Timing {
  double setup = 0, solve = 0;
  std::vector<int> iterations;
};

/// Solves every system with `method`; set-up and solve times summed over the systems.
Timing run_method(const std::string& method, const std::vector<System>& systems,
                  const multigrid::GeometricMultigrid<3>& mg, const fem::VectorSpace<3>& space,
                  const mapping::Map<3>& map) {
  Timing t;
  for (const System& s : systems) {
    petsc::LinearSolver ksp;
    WARPFEM_PETSC_CHECK(KSPCreate(space.comm(), ksp.out()));
    std::string prefix = method + "_";
    std::replace(prefix.begin(), prefix.end(), '-', '_');
    WARPFEM_PETSC_CHECK(KSPSetOptionsPrefix(ksp.get(), prefix.c_str()));
    WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), method == "lu" ? KSPPREONLY : KSPGMRES));
    WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp.get(), 1e-8, 1e-50, PETSC_DEFAULT, 500));
    PC pc = nullptr;
    WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
    Stopwatch watch;
    if (method == "gmg") {
      mg.configure(ksp.get(), {s.J.get()});
    } else {
      WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), s.J.get(), s.J.get()));
      if (method == "gamg" || method == "hypre-nodal")
        fem::set_rigid_body_near_null_space(s.J.get(), space, map);
      if (method == "gamg") WARPFEM_PETSC_CHECK(PCSetType(pc, PCGAMG));
      if (method.starts_with("hypre")) {
        WARPFEM_PETSC_CHECK(PCSetType(pc, PCHYPRE));
        WARPFEM_PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
      }
      if (method == "lu") {
        WARPFEM_PETSC_CHECK(PCSetType(pc, PCLU));
        WARPFEM_PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
      }
    }
    WARPFEM_PETSC_CHECK(KSPSetFromOptions(ksp.get()));
    WARPFEM_PETSC_CHECK(KSPSetUp(ksp.get()));
    WARPFEM_PETSC_CHECK(PCSetUp(pc));
    t.setup += watch.seconds();
    petsc::Vector x;
    WARPFEM_PETSC_CHECK(VecDuplicate(s.b.get(), x.out()));
    watch.reset();
    WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), s.b.get(), x.get()));
    t.solve += watch.seconds();
    KSPConvergedReason reason;
    WARPFEM_PETSC_CHECK(KSPGetConvergedReason(ksp.get(), &reason));
    PetscInt its = 0;
    WARPFEM_PETSC_CHECK(KSPGetIterationNumber(ksp.get(), &its));
    t.iterations.push_back(reason > 0 ? static_cast<int>(its) : -static_cast<int>(its));
    if (method == "gamg" || method == "hypre-nodal")
      WARPFEM_PETSC_CHECK(MatSetNearNullSpace(s.J.get(), nullptr));
  }
  return t;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int run(int argc, char** argv) {
  Environment env(argc, argv);
  log::set_level(log::Level::warning);
  // Defaults of the hypre variants, unless the command line says otherwise. (Interpolation
  // refined with the rigid-body modes, ..._vec_interp_variant 1 or 2, saves an iteration or
  // two and costs about 8x in set-up and solve on these problems.)
  const std::pair<const char*, const char*> defaults[] = {
      {"-hypre_3d_pc_hypre_boomeramg_coarsen_type", "HMIS"},
      {"-hypre_3d_pc_hypre_boomeramg_interp_type", "ext+i"},
      {"-hypre_3d_pc_hypre_boomeramg_P_max", "4"},
      {"-hypre_3d_pc_hypre_boomeramg_strong_threshold", "0.5"},
      {"-hypre_nodal_pc_hypre_boomeramg_nodal_coarsen", "6"}};
  for (const auto& [name, value] : defaults) {
    PetscBool set = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, name, &set));
    if (!set) WARPFEM_PETSC_CHECK(PetscOptionsSetValue(nullptr, name, value));
  }
  const CellType type =
      string_option("-type", "hexahedron") == "tetrahedron" ? CellType::tetrahedron : CellType::hexahedron;
  const int order = static_cast<int>(int_option("-order", 1));
  const int n = static_cast<int>(int_option("-n", 2));
  const int refinements = static_cast<int>(int_option("-refinements", 3));
  const int rounds = static_cast<int>(int_option("-rounds", 3));
  PetscBool with_lu = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, "-lu", &with_lu));
  std::vector<std::string> methods = {"gmg", "gamg", "hypre", "hypre-3d", "hypre-nodal"};
  if (with_lu) methods.push_back("lu");

  Stopwatch watch;
  const fem::MeshHierarchy<3> hierarchy(
      structured_box_mesh(Point<3>::Zero(), Point<3>(2, 1, 1), {2 * n, n, n}, type), refinements);
  const auto map = std::make_shared<WarpedBox>();
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, hierarchy.finest(), map, order, 0,
                                     compressed_twisted_bar());
  const multigrid::GeometricMultigrid<3> mg(hierarchy, op);
  const double setup = watch.seconds();

  std::vector<System> systems;
  fem::NewtonOptions newton;
  newton.log_iterations = false;
  newton.rtol = 1e-8;
  newton.ksp_type = "gmres";
  newton.configure_preconditioner = [&systems, &mg](KSP ksp, Mat jacobian) {
    WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp, 1e-10, 1e-50, PETSC_DEFAULT, 500));
    mg.configure(ksp, {jacobian});
    WARPFEM_PETSC_CHECK(KSPSetPreSolve(ksp, record, &systems));
  };
  petsc::Vector u = op.space().create_vector();
  watch.reset();
  fem::QuasiStaticSolver solver(op, newton, {.steps = 2});
  const fem::QuasiStaticReport report = solver.solve(u.get());
  const double newton_seconds = watch.seconds();

  std::vector<std::vector<double>> setups(methods.size()), solves(methods.size());
  std::vector<std::vector<int>> iterations(methods.size());
  for (int r = 0; r < rounds; ++r)
    for (std::size_t k = 0; k < methods.size(); ++k) {
      const std::size_t m = r % 2 ? methods.size() - 1 - k : k;  // alternate the order
      const Timing t = run_method(methods[m], systems, mg, op.space(), *map);
      setups[m].push_back(t.setup);
      solves[m].push_back(t.solve);
      iterations[m] = t.iterations;
    }
  if (Environment::rank() != 0) return 0;
  const char* element =
      type == CellType::hexahedron ? (order == 1 ? "Q1" : "Q2") : (order == 1 ? "P1" : "P2");
  std::printf("\n### 3D neo-Hookean box, %s, %d levels, %lld DOFs, %d rank(s)\n\n", element, mg.num_levels(),
              static_cast<long long>(op.space().num_global()), Environment::size());
  std::printf(
      "operator + multigrid set-up %.2f s; Newton (GMRES + geometric multigrid) %.2f s: %d Newton steps in "
      "%zu load steps, "
      "%zu linear systems (incl. predictors)\n\n",
      setup, newton_seconds, report.newton_iterations(), report.steps.size(), systems.size());
  std::printf("GMRES to 1e-8 relative; times summed over the systems, median of %d rounds.\n\n", rounds);
  std::printf(
      "| method | iterations per system | set-up [s] | solve [s] | total [s] |\n|---|---|---|---|---|\n");
  for (std::size_t m = 0; m < methods.size(); ++m) {
    std::string its;
    for (int i : iterations[m]) its += (its.empty() ? "" : " ") + std::to_string(i);
    const double s = median(setups[m]), v = median(solves[m]);
    std::printf("| %s | %s | %.3f | %.3f | %.3f |\n", methods[m].c_str(), its.c_str(), s, v, s + v);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
