// 3D Poisson on the unit cube (identity map, −Δu = 1, u = 0 on the boundary):
// the geometric multigrid solver (hierarchy, per-level problems and assembly,
// prolongations, PCMG set-up, CG solve to 1e-8 relative) against PETSc GAMG
// on the same finest matrix and right-hand side, in the same process.
//
//   bench_poisson_3d [-type hexahedron|tetrahedron] [-order 1|2] [-n 2] [-refinements 5]
//
// -n: cells per side of the coarse mesh; the finest has n · 2^refinements.

#include <cstdio>
#include <exception>
#include <string>

#include "core/environment.hpp"
#include "core/log.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"
#include "multigrid/poisson_multigrid.hpp"

using namespace warpfem;

namespace {

PetscInt int_option(const char* name, PetscInt fallback) {
  PetscInt v = fallback;
  WARPFEM_PETSC_CHECK(PetscOptionsGetInt(nullptr, nullptr, name, &v, nullptr));
  return v;
}

std::string string_option(const char* name, const char* fallback) {
  char buf[PETSC_MAX_PATH_LEN] = {0};
  PetscBool set = PETSC_FALSE;
  WARPFEM_PETSC_CHECK(PetscOptionsGetString(nullptr, nullptr, name, buf, sizeof buf, &set));
  return set ? buf : fallback;
}

int run(int argc, char** argv) {
  Environment env(argc, argv);
  log::set_level(log::Level::warning);
  const CellType type =
      string_option("-type", "hexahedron") == "tetrahedron" ? CellType::tetrahedron : CellType::hexahedron;
  const int order = static_cast<int>(int_option("-order", 1));
  const int n = static_cast<int>(int_option("-n", 2));
  const int refinements = static_cast<int>(int_option("-refinements", 5));

  fem::PoissonData<3> data;
  data.dirichlet.push_back({.edges = {}, .value = [](const Point<3>&, double) { return 0.0; }});
  data.source = fem::ConstantFunction{1.0};
  multigrid::PoissonMultigridOptions options;
  options.linear.rtol = 1e-8;
  Stopwatch total;
  multigrid::PoissonMultigridSolver<3> mg(
      PETSC_COMM_WORLD, structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), {n, n, n}, type),
      refinements, std::make_shared<mapping::IdentityMap<3>>(), order, 2 * order + 1, data, options);
  const auto report = mg.solve();
  const double mg_total = total.seconds();
  const auto& t = report.timings;
  std::printf("%s order %d, %d levels, %lld DOFs\n", to_string(type).c_str(), order, report.levels,
              static_cast<long long>(report.level_dofs.back()));
  std::printf(
      "GMG: hierarchy %.3f s, problems %.3f s, assembly %.3f s (finest %.3f s), transfers %.3f s, "
      "PC set-up %.3f s, solve %.3f s, %d its; total %.3f s\n",
      t.hierarchy, t.problems, t.assembly, t.finest_assembly, t.transfers, t.pc_setup,
      report.linear.solve_seconds, report.linear.iterations, mg_total);

  // GAMG on the same matrix and right-hand side, from zero.
  const fem::PoissonProblem<3>& p = mg.finest();
  petsc::Vector x = p.create_vector();
  petsc::LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_WORLD, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOptionsPrefix(ksp.get(), "amg_"));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), p.matrix(), p.matrix()));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), KSPCG));
  WARPFEM_PETSC_CHECK(KSPSetNormType(ksp.get(), KSP_NORM_UNPRECONDITIONED));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp.get(), 1e-8, 1e-50, PETSC_DEFAULT, 1000));
  PC pc;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, PCGAMG));
  WARPFEM_PETSC_CHECK(KSPSetFromOptions(ksp.get()));
  Stopwatch watch;
  WARPFEM_PETSC_CHECK(KSPSetUp(ksp.get()));
  const double setup = watch.seconds();
  watch.reset();
  WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), p.rhs(), x.get()));
  const double solve = watch.seconds();
  PetscInt its = 0;
  WARPFEM_PETSC_CHECK(KSPGetIterationNumber(ksp.get(), &its));
  std::printf(
      "GAMG (same matrix): set-up %.3f s, solve %.3f s, %lld its; set-up + solve %.3f s against "
      "GMG's PC set-up + solve %.3f s\n",
      setup, solve, static_cast<long long>(its), setup + solve, t.pc_setup + report.linear.solve_seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_poisson_3d: %s\n", e.what());
    return 1;
  }
}
