// 3D Poisson −Δu = 1, u = 0 on the boundary, on the unit cube (identity map)
// or on the unit ball (-domain ball: the box [-1,1]³ under the analytic map of
// cube_to_ball_map.hpp, the domain of bench/dealii/poisson_ball.cc): the
// geometric multigrid solver (hierarchy, per-level problems and assembly,
// prolongations, PCMG set-up, CG solve to 1e-8 relative) against PETSc GAMG
// and hypre BoomerAMG (through PETSc) on the same finest matrix and
// right-hand side, in the same process, in alternated rounds.
//
//   bench_poisson_3d [-type hexahedron|tetrahedron] [-order 1|2] [-n 2] [-refinements 5]
//                    [-qdeg 2 order + 1] [-geometry cached|streamed] [-rounds 1]
//                    [-peers gmg,gamg,hypre] [-partial_levels 1] [-domain cube|ball]
//
// -n: cells per side of the coarse mesh; the finest has n · 2^refinements.
// -partial_levels 0: under MPI every rank stores every level whole (default 1:
// P1 / Q1 levels above the partition's base only around the rank's cells).
// Every phase is reported in wall and in process CPU seconds (the CPU figure
// counts the run's own work on a host shared with other jobs; one thread).
// The AMG peers are charged the finest problem's construction and assembly
// (what they need of warpfem), then their KSPSetUp and KSPSolve. Without
// "gmg" in -peers the finest problem is built alone (no hierarchy kept), so
// that the peak RSS of the run is the peer's own; memory is also reported as
// resident-set growth over each phase (PetscMemoryGetCurrentUsage).
// A peer is GAMG if its name starts with "gamg", BoomerAMG if with "hypre";
// its options go through the prefix <name>_ (-gamg_pc_gamg_threshold 0.02,
// -hypre_pc_hypre_boomeramg_strong_threshold 0.5, ...), so that variants run
// side by side (-peers gmg,hypre,hypre_hmis -hypre_hmis_pc_hypre_boomeramg_...).
// On the ball, the map is first checked on probes (det J_f > 0 up to the
// cube's edges and corners, J_f against differences, faces onto the sphere),
// and after each round the L2 error against the exact u = (1 − |x|²)/6 and
// max u (1/6 exactly) are printed, outside the timed phases, to compare with
// deal.II's solution of the same problem.

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_options.hpp"
#include "bench/multigrid/cube_to_ball_map.hpp"
#include "core/environment.hpp"
#include "core/log.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"
#include "multigrid/poisson_multigrid.hpp"

using namespace warpfem;
using bench::int_option;
using bench::string_option;

namespace {

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double resident_megabytes() {
  PetscLogDouble bytes = 0;
  WARPFEM_PETSC_CHECK(PetscMemoryGetCurrentUsage(&bytes));
  return bytes / 1048576.0;
}

/// Wall and CPU seconds and resident-set growth (MB) since construction.
struct Meter {
  Stopwatch wall;
  double cpu0 = cpu_seconds(), rss0 = resident_megabytes();
  struct Reading {
    double wall = 0, cpu = 0, rss = 0;
  };
  Reading read() const { return {wall.seconds(), cpu_seconds() - cpu0, resident_megabytes() - rss0}; }
};

struct Case {
  CellType type = CellType::hexahedron;
  int order = 1, n = 2, refinements = 5, qdeg = 3;
  fem::GeometryStorage geometry = fem::GeometryStorage::cached;
  bool partial_levels = true;
  bool ball = false;  ///< the box [-1,1]³ mapped onto the unit ball, else the unit cube
};

mapping::MapPtr<3> domain_map(const Case& c) {
  if (c.ball) return std::make_shared<bench::CubeToBallMap>();
  return std::make_shared<mapping::IdentityMap<3>>();
}

fem::PoissonData<3> poisson_data() {
  fem::PoissonData<3> data;
  data.dirichlet.push_back({.edges = {}, .value = [](const Point<3>&, double) { return 0.0; }});
  data.source = fem::ConstantFunction{1.0};
  return data;
}

Mesh<3> coarse_mesh(const Case& c) {
  const double low = c.ball ? -1 : 0;
  return structured_box_mesh(Point<3>(low, low, low), Point<3>(1, 1, 1), {c.n, c.n, c.n}, c.type);
}

/// CG with `pc` ("gamg" or "hypre") on A x = b from zero; returns false if it did not converge.
bool run_amg(const std::string& pc_name, Mat A, Vec b, Vec x, const Meter::Reading& assembly,
             double gmg_cpu_total, Index dofs) {
  WARPFEM_PETSC_CHECK(VecSet(x, 0.0));
  petsc::LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(PETSC_COMM_WORLD, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOptionsPrefix(ksp.get(), (pc_name + "_").c_str()));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), A, A));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), KSPCG));
  WARPFEM_PETSC_CHECK(KSPSetNormType(ksp.get(), KSP_NORM_UNPRECONDITIONED));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp.get(), 1e-8, 1e-50, PETSC_DEFAULT, 1000));
  PC pc;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
  if (pc_name.starts_with("hypre")) {
    WARPFEM_PETSC_CHECK(PCSetType(pc, PCHYPRE));
    WARPFEM_PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
  } else {
    WARPFEM_PETSC_CHECK(PCSetType(pc, PCGAMG));
  }
  WARPFEM_PETSC_CHECK(KSPSetFromOptions(ksp.get()));
  Meter setup_meter;
  WARPFEM_PETSC_CHECK(KSPSetUp(ksp.get()));
  const Meter::Reading setup = setup_meter.read();
  Meter solve_meter;
  WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), b, x));
  const Meter::Reading solve = solve_meter.read();
  PetscInt its = 0;
  KSPConvergedReason reason;
  WARPFEM_PETSC_CHECK(KSPGetIterationNumber(ksp.get(), &its));
  WARPFEM_PETSC_CHECK(KSPGetConvergedReason(ksp.get(), &reason));
  const double total_cpu = assembly.cpu + setup.cpu + solve.cpu;
  std::printf(
      "%-5s: set-up %.3f s (CPU %.3f s), solve %.3f s (CPU %.3f s), %lld its%s; with the finest "
      "assembly CPU %.3f s%s; memory +%.0f MB set-up +%.0f MB solve (%.0f bytes/DOF)\n",
      pc_name.c_str(), setup.wall, setup.cpu, solve.wall, solve.cpu, static_cast<long long>(its),
      reason > 0 ? "" : " (NOT CONVERGED)", total_cpu,
      gmg_cpu_total > 0 ? (", GMG/" + pc_name + " " + std::to_string(gmg_cpu_total / total_cpu)).c_str() : "",
      setup.rss, solve.rss, (setup.rss + solve.rss) * 1048576.0 / static_cast<double>(dofs));
  return reason > 0;
}

/// Relative max difference of two solutions.
double relative_difference(Vec x, Vec y) {
  petsc::Vector d;
  WARPFEM_PETSC_CHECK(VecDuplicate(x, d.out()));
  WARPFEM_PETSC_CHECK(VecWAXPY(d.get(), -1.0, y, x));
  PetscReal nd = 0, nx = 0;
  WARPFEM_PETSC_CHECK(VecNorm(d.get(), NORM_INFINITY, &nd));
  WARPFEM_PETSC_CHECK(VecNorm(x, NORM_INFINITY, &nx));
  return nx > 0 ? nd / nx : nd;
}

/// The ball's solution against the exact u = (1 − |x|²)/6 (after the timed phases).
void report_ball_solution(const fem::PoissonProblem<3>& p) {
  const auto e = p.errors([](const Point<3>& x, double) { return (1 - x.squaredNorm()) / 6; },
                          [](const Point<3>& x, double) -> Point<3> { return -x / 3; });
  PetscReal max_u = 0;
  WARPFEM_PETSC_CHECK(VecMax(p.solution(), nullptr, &max_u));
  std::printf("ball : L2 error %.4e, H1-seminorm error %.4e against (1 - |x|^2)/6; max u %.6e (exact %.6e)\n",
              e.l2, e.h1_semi, max_u, 1.0 / 6);
}

/// One round: the geometric multigrid end to end, then the AMG peers on its finest matrix.
void round_with_gmg(const Case& c, const std::vector<std::string>& amg, int round) {
  multigrid::PoissonMultigridOptions options;
  options.linear.rtol = 1e-8;
  options.finest_geometry = c.geometry;
  options.partial_levels = c.partial_levels;
  Meter setup_meter;
  multigrid::PoissonMultigridSolver<3> mg(PETSC_COMM_WORLD, coarse_mesh(c), c.refinements, domain_map(c),
                                          c.order, c.qdeg, poisson_data(), options);
  const Meter::Reading setup = setup_meter.read();
  Meter solve_meter;
  const auto report = mg.solve();
  const Meter::Reading solve = solve_meter.read();
  const auto& t = report.timings;
  const Index dofs = report.level_dofs.back();
  const fem::PoissonProblem<3>& p = mg.finest();
  if (c.ball) report_ball_solution(p);
  if (round == 0)
    std::printf("%s order %d, quadrature degree %d, %d levels, %lld DOFs, %lld cells, %s finest geometry\n",
                to_string(c.type).c_str(), c.order, c.qdeg, report.levels, static_cast<long long>(dofs),
                static_cast<long long>(p.mesh().num_cells()),
                c.geometry == fem::GeometryStorage::cached ? "cached" : "streamed");
  std::printf("round %d\n", round + 1);
  std::printf(
      "GMG  : hierarchy %.3f s, problems %.3f s, assembly %.3f s (finest %.3f s), transfers %.3f s, "
      "PC set-up %.3f s, solve %.3f s, %d its; total %.3f s\n",
      t.hierarchy, t.problems, t.assembly, t.finest_assembly, t.transfers, t.pc_setup,
      report.linear.solve_seconds, report.linear.iterations, setup.wall + solve.wall);
  const auto& pp = t.problem_parts;
  std::printf(
      "GMG  : problems: DOF maps %.3f s, distributions %.3f s, geometry %.3f s, matrices %.3f s, "
      "other %.3f s\n",
      pp.dof_map, pp.distribution, pp.geometry, pp.matrix, pp.other);
  const double gmg_cpu = setup.cpu + solve.cpu;
  std::printf("GMG  : CPU set-up %.3f s + solve %.3f s = %.3f s; memory +%.0f MB (%.0f bytes/DOF)\n",
              setup.cpu, solve.cpu, gmg_cpu, setup.rss + solve.rss,
              (setup.rss + solve.rss) * 1048576.0 / static_cast<double>(dofs));
  // The peers are charged the finest level's problem and assembly.
  const Meter::Reading assembly{t.finest_problem + t.finest_assembly, t.finest_cpu, 0};
  std::printf("GMG  : finest problem + assembly %.3f s (CPU %.3f s)\n", assembly.wall, assembly.cpu);
  petsc::Vector x = p.create_vector();
  for (std::size_t k = 0; k < amg.size(); ++k) {
    const std::string& name = amg[(k + static_cast<std::size_t>(round)) % amg.size()];
    if (run_amg(name, p.matrix(), p.rhs(), x.get(), assembly, gmg_cpu, dofs))
      std::printf("%-5s: solution differs from GMG's by %.1e (relative, max norm)\n", name.c_str(),
                  relative_difference(p.solution(), x.get()));
  }
}

/// One round of the AMG peers alone on the finest problem (built without keeping a hierarchy).
void round_without_gmg(const Case& c, const std::vector<std::string>& amg, int round) {
  Meter meter;
  Mesh<3> fine = [&] {
    fem::MeshHierarchy<3> h(coarse_mesh(c), c.refinements);
    return std::move(h.levels.back());
  }();
  fem::PoissonProblem<3> p(PETSC_COMM_WORLD, fine, domain_map(c), c.order, c.qdeg, poisson_data(),
                           c.geometry);
  p.assemble();
  const Meter::Reading assembly = meter.read();
  const Index dofs = p.dofs().num_dofs();
  std::printf("round %d: %lld DOFs; mesh, problem and assembly %.3f s (CPU %.3f s), +%.0f MB\n", round + 1,
              static_cast<long long>(dofs), assembly.wall, assembly.cpu, assembly.rss);
  petsc::Vector x = p.create_vector();
  for (std::size_t k = 0; k < amg.size(); ++k)
    run_amg(amg[(k + static_cast<std::size_t>(round)) % amg.size()], p.matrix(), p.rhs(), x.get(), assembly,
            0, dofs);
}

int run(int argc, char** argv) {
  Environment env(argc, argv);
  log::set_level(log::Level::warning);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // rounds appear as they finish, also in a pipe
  Case c;
  c.type =
      string_option("-type", "hexahedron") == "tetrahedron" ? CellType::tetrahedron : CellType::hexahedron;
  c.order = static_cast<int>(int_option("-order", 1));
  c.n = static_cast<int>(int_option("-n", 2));
  c.refinements = static_cast<int>(int_option("-refinements", 5));
  c.qdeg = static_cast<int>(int_option("-qdeg", 2 * c.order + 1));
  c.geometry = string_option("-geometry", "cached") == "streamed" ? fem::GeometryStorage::streamed
                                                                  : fem::GeometryStorage::cached;
  c.partial_levels = int_option("-partial_levels", 1) != 0;
  c.ball = string_option("-domain", "cube") == "ball";
  if (c.ball) {
    const bench::CubeToBallCheck check = bench::check_cube_to_ball(bench::CubeToBallMap());
    std::printf(
        "cube-to-ball map: min det J %.3e on the grid 0.05 inside, %.3e on probes 1e-6..1e-1 from corners, "
        "edges and faces; J vs differences %.1e; | |f| - 1 | on the faces %.1e\n",
        check.min_det_interior, check.min_det_near_boundary, check.max_jacobian_error,
        check.max_sphere_error);
    if (!check.ok) throw std::runtime_error("the cube-to-ball map failed its check");
  }
  const int rounds = static_cast<int>(int_option("-rounds", 1));
  const std::string peers = "," + string_option("-peers", "gmg,gamg,hypre") + ",";
  const bool with_gmg = peers.find(",gmg,") != std::string::npos;
  // AMG peers: every name in -peers that starts with gamg or hypre, each with
  // its own options prefix (e.g. hypre and hypre_tuned side by side).
  std::vector<std::string> amg;
  for (std::size_t at = 1; at < peers.size();) {
    const std::size_t end = peers.find(',', at);
    const std::string name = peers.substr(at, end - at);
    if (name.starts_with("gamg") || name.starts_with("hypre")) amg.push_back(name);
    at = end + 1;
  }
  for (int r = 0; r < rounds; ++r) {
    if (with_gmg)
      round_with_gmg(c, amg, r);
    else
      round_without_gmg(c, amg, r);
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  std::printf("peak RSS %.0f MB (rank %d)\n", static_cast<double>(usage.ru_maxrss) / 1024.0, rank);
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
