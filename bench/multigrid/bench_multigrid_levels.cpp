// Level study of geometric multigrid (PCMG with our nested prolongations)
// against PETSc GAMG and hypre BoomerAMG, on the same matrices, right-hand
// sides and initial guesses: CG to a 1e-8 relative (unpreconditioned) residual.
//
//   build/bench/multigrid/bench_multigrid_levels -order 1 -max_refinements 6 -map composite
//   mpiexec -n 2 build/bench/multigrid/bench_multigrid_levels -order 1 -min_refinements 6 -max_refinements 6
//
// Options: -order 1|2, -cells triangle|quad, -coarse_h <h> (0.3), -structured <n> (an n x n structured
// coarse mesh of a rectangular source instead of the Delaunay one), -min_refinements/-max_refinements,
// -map identity|composite (L-shape to an L-shape with a pulled re-entrant corner; -target x0,y0,...,x5,y5
// gives another target hexagon), -map_config <file.json> (the map of a config file instead, e.g.
// examples/study_gear64.json: Ω0 is its source polygon), -amg 0|1, -galerkin 0|1, -prolongation
// geometric|smoothed (smoothed_prolongation.hpp; Galerkin operators come with it), -smoother
// chebyshev_jacobi|chebyshev_sor|sor, -smoothing_steps k and -chebyshev_kernel
// petsc|fused_double|fused_single (solver.multigrid of a run config), -quadrature_degree <q> (default
// warpfem::default_quadrature_degree(order)), -stream_finest 0|1 (the finest level's geometry streamed
// instead of cached; coarse levels are always streamed), -whole_levels 1 (every rank holds every level whole
// instead of the P1 levels above the partition's base only around its cells), -pullback 1 (coarse mesh:
// CGAL's mesh of the map's target pulled back through f⁻¹, -coarse_h in target units), -prerefine k (refine
// the coarse mesh k times before the hierarchy starts, e.g. with -mg_coarse_pc_type hypre). MG set-up =
// refinement + per-level problems + assembly of every level + prolongations + KSPSetUp. AMG set-up = KSPSetUp
// only (the finest matrix is shared, its assembly is the "fine asm" column). Any PETSc option applies
// (-log_view, -mg_levels_ksp_type richardson, -amg_pc_gamg_threshold 0.05, ...); P1/Q1 Chebyshev smoothers
// use Gershgorin bounds (no eigenvalue estimates): -mg_levels_ksp_chebyshev_esteig 0,0.1,0,1.1 brings the
// estimate back.

#include <cstdio>
#include <exception>
#include <string>

#include "bench/bench_options.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"
#include "fem/hierarchy/pullback_mesher.hpp"
#include "io/run_config.hpp"
#include "mapping/make_map.hpp"
#include "multigrid/poisson_multigrid.hpp"

using namespace warpfem;
using bench::int_option;
using bench::string_option;

namespace {

struct AmgResult {
  double setup = 0, solve = 0;
  int iterations = 0;
};

AmgResult solve_amg(Mat A, Vec b, Vec x0, const char* pc_type) {
  AmgResult r;
  MPI_Comm comm;
  WARPFEM_PETSC_CHECK(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  petsc::Vector x;
  WARPFEM_PETSC_CHECK(VecDuplicate(x0, x.out()));
  WARPFEM_PETSC_CHECK(VecCopy(x0, x.get()));
  petsc::LinearSolver ksp;
  WARPFEM_PETSC_CHECK(KSPCreate(comm, ksp.out()));
  WARPFEM_PETSC_CHECK(KSPSetOptionsPrefix(ksp.get(), "amg_"));
  WARPFEM_PETSC_CHECK(KSPSetOperators(ksp.get(), A, A));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp.get(), KSPCG));
  WARPFEM_PETSC_CHECK(KSPSetNormType(ksp.get(), KSP_NORM_UNPRECONDITIONED));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp.get(), 1e-8, 1e-50, PETSC_DEFAULT, 1000));
  WARPFEM_PETSC_CHECK(KSPSetInitialGuessNonzero(ksp.get(), PETSC_TRUE));
  PC pc;
  WARPFEM_PETSC_CHECK(KSPGetPC(ksp.get(), &pc));
  WARPFEM_PETSC_CHECK(PCSetType(pc, pc_type));
  if (std::string(pc_type) == PCHYPRE) WARPFEM_PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
  WARPFEM_PETSC_CHECK(KSPSetFromOptions(ksp.get()));
  Stopwatch watch;
  WARPFEM_PETSC_CHECK(KSPSetUp(ksp.get()));
  r.setup = watch.seconds();
  watch.reset();
  WARPFEM_PETSC_CHECK(KSPSolve(ksp.get(), b, x.get()));
  r.solve = watch.seconds();
  PetscInt its = 0;
  WARPFEM_PETSC_CHECK(KSPGetIterationNumber(ksp.get(), &its));
  KSPConvergedReason reason;
  WARPFEM_PETSC_CHECK(KSPGetConvergedReason(ksp.get(), &reason));
  r.iterations = reason > 0 ? static_cast<int>(its) : -static_cast<int>(its);
  return r;
}

}  // namespace

int run(int argc, char** argv) {
  Environment env(argc, argv);
  log::set_level(log::Level::warning);
  const int order = static_cast<int>(int_option("-order", 1));
  const int rmin = static_cast<int>(int_option("-min_refinements", 1));
  const int rmax = static_cast<int>(int_option("-max_refinements", 5));
  const bool amg = int_option("-amg", 1) != 0;
  const bool galerkin = int_option("-galerkin", 0) != 0;
  // solver.multigrid.prolongation: geometric (default) | smoothed
  const std::string prolongation = string_option("-prolongation", "geometric");
  if (prolongation != "geometric" && prolongation != "smoothed")
    throw Error("-prolongation " + prolongation + ": expected geometric or smoothed");
  // The config's solver.multigrid.smoother / smoothing_steps (defaults: chebyshev_jacobi, 0 = automatic).
  const std::string smoother = string_option("-smoother", "chebyshev_jacobi");
  const int smoothing_steps = static_cast<int>(int_option("-smoothing_steps", 0));
  // solver.multigrid.chebyshev_kernel: petsc | fused_double | fused_single (default)
  const std::string kernel = string_option("-chebyshev_kernel", "fused_single");
  if (kernel != "petsc" && kernel != "fused_double" && kernel != "fused_single")
    throw Error("-chebyshev_kernel " + kernel + ": expected petsc, fused_double or fused_single");
  if (smoother != "chebyshev_jacobi" && smoother != "chebyshev_sor" && smoother != "sor")
    throw Error("-smoother " + smoother + ": expected chebyshev_jacobi, chebyshev_sor or sor");
  const bool stream_finest = int_option("-stream_finest", 0) != 0;
  const bool whole_levels = int_option("-whole_levels", 0) != 0;
  const std::string map_type = string_option("-map", "identity");
  const bool quads = string_option("-cells", "triangle") == "quad";
  const int qdeg =
      static_cast<int>(int_option("-quadrature_degree", warpfem::default_quadrature_degree(order)));
  PetscReal coarse_h = 0.3;
  WARPFEM_PETSC_CHECK(PetscOptionsGetReal(nullptr, nullptr, "-coarse_h", &coarse_h, nullptr));

  // 1. Geometry: the L-shape Ω0 and a map (identity, or a composite mean value map to a bent L),
  // or the map of a config file.
  const std::string map_config = string_option("-map_config", "");
  mapping::MapSpec spec;
  if (!map_config.empty()) {
    spec = io::parse_required_map(io::ConfigNode(io::ConfigNode::parse_file(map_config), map_config));
  } else {
    spec.type = map_type == "composite" ? "composite_mean_value" : "identity";
    spec.source = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L-shape");
    PetscReal t[12] = {0, 0, 2, 0, 2.2, 1.4, 1.3, 0.8, 1.1, 2, -0.2, 1.8};
    PetscInt nt = 12;
    WARPFEM_PETSC_CHECK(PetscOptionsGetRealArray(nullptr, nullptr, "-target", t, &nt, nullptr));
    std::vector<Point<2>> target;
    for (int i = 0; i < 6; ++i) target.emplace_back(t[2 * i], t[2 * i + 1]);
    spec.target = Polygon::checked(target, "target L");
  }
  const Polygon source = *spec.source;
  Stopwatch watch;
  const mapping::MapPtr<2> map = mapping::make_map(spec);
  const double map_seconds = watch.seconds();
  const PetscInt structured = int_option("-structured", 0);  // n x n structured coarse mesh instead
  const bool pullback = int_option("-pullback", 0) != 0;     // mesh Ω1, pull the mesh back through f⁻¹
  fem::PullbackReport pullback_report;
  warpfem::Mesh<2> coarse =
      structured > 0
          ? warpfem::structured_mesh(source, static_cast<int>(structured), static_cast<int>(structured),
                                     quads ? warpfem::CellType::quadrilateral : warpfem::CellType::triangle)
      : pullback ? fem::pull_back_target_mesh(source, spec.target ? *spec.target : source, *map,
                                              {.max_edge_length = coarse_h}, &pullback_report)
                 : warpfem::mesh_polygon(source, {.max_edge_length = coarse_h});
  if (quads && structured == 0) coarse = warpfem::split_into_quadrilaterals(coarse);
  if (pullback && Environment::rank() == 0)
    std::printf(
        "# pulled-back coarse mesh: %ld cells, %d fold repairs, max distortion %.3g, min area ratio %.3g\n",
        static_cast<long>(coarse.num_cells()), pullback_report.fold_repairs, pullback_report.max_distortion,
        pullback_report.min_area_ratio);
  // -prerefine k: refine the coarse mesh k times first, so PCMG gets only the finer levels (its
  // coarse solve, e.g. -mg_coarse_pc_type hypre, then works on a mid-size level).
  for (PetscInt k = int_option("-prerefine", 0); k > 0; --k) coarse = warpfem::refine_uniformly(coarse).mesh;

  // 2. Problem: −Δu = 1 on f(Ω0), u = 0 on the whole boundary.
  fem::PoissonData<2> data;
  data.source = fem::ConstantFunction{1.0};
  data.dirichlet.push_back({.edges = {}, .value = [](const Point<2>&, double) { return 0.0; }});

  if (Environment::rank() == 0) {
    std::printf(
        "# %s%d, map %s (built in %.3f s), %d rank(s), coarse h %.3g, quadrature degree %d, "
        "CG to 1e-8 relative residual\n",
        quads ? "Q" : "P", order, map->describe().c_str(), map_seconds, Environment::size(), coarse_h, qdeg);
    std::printf("%6s %10s | %8s %8s %8s %8s %8s %8s %4s %9s | %8s %8s %4s | %8s %8s %4s\n", "levels", "DOFs",
                "refine", "problems", "assembly", "fine asm", "transfer", "pcsetup", "its", "solve",
                "gamg set", "solve", "its", "hypre st", "solve", "its");
  }
  for (int r = rmin; r <= rmax; ++r) {
    multigrid::PoissonMultigridOptions options;
    if (stream_finest) options.finest_geometry = fem::GeometryStorage::streamed;
    options.partial_levels = !whole_levels;
    if (galerkin)
      options.multigrid.coarse_operators = multigrid::MultigridSettings::CoarseOperators::galerkin;
    if (prolongation == "smoothed")
      options.multigrid.prolongation = multigrid::MultigridSettings::Prolongation::smoothed;
    using Smoother = multigrid::MultigridSettings::Smoother;
    options.multigrid.smoother = smoother == "sor"             ? Smoother::sor
                                 : smoother == "chebyshev_sor" ? Smoother::chebyshev_sor
                                                               : Smoother::chebyshev_jacobi;
    options.multigrid.smoothing_steps = smoothing_steps;
    using Kernel = multigrid::MultigridSettings::ChebyshevKernel;
    options.multigrid.chebyshev_kernel = kernel == "petsc"          ? Kernel::petsc
                                         : kernel == "fused_double" ? Kernel::fused_double
                                                                    : Kernel::fused_single;
    multigrid::PoissonMultigridSolver<2> mg(PETSC_COMM_WORLD, coarse, r, map, order, qdeg, data, options);
    fem::PoissonProblem<2>& fine = mg.finest();
    petsc::Vector u0;
    WARPFEM_PETSC_CHECK(VecDuplicate(fine.solution(), u0.out()));
    WARPFEM_PETSC_CHECK(VecCopy(fine.solution(), u0.get()));
    const auto rep = mg.solve();
    const auto& t = rep.timings;
    AmgResult gamg, hypre;
    if (amg) {
      gamg = solve_amg(fine.matrix(), fine.rhs(), u0.get(), PCGAMG);
      hypre = solve_amg(fine.matrix(), fine.rhs(), u0.get(), PCHYPRE);
    }
    if (Environment::rank() == 0) {
      std::printf(
          "%6d %10lld | %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %4d %9.4f | %8.3f %8.3f %4d | %8.3f %8.3f %4d\n",
          rep.levels, static_cast<long long>(rep.level_dofs.back()), t.hierarchy, t.problems, t.assembly,
          t.finest_assembly, t.transfers, t.pc_setup, rep.linear.iterations, rep.linear.solve_seconds,
          gamg.setup, gamg.solve, gamg.iterations, hypre.setup, hypre.solve, hypre.iterations);
      std::printf("%17s MG total set-up %.3f s, set-up + solve %.3f s, solve per DOF %.1f ns\n", "",
                  t.setup(), t.setup() + rep.linear.solve_seconds,
                  1e9 * rep.linear.solve_seconds / static_cast<double>(rep.level_dofs.back()));
      const auto& pp = t.problem_parts;
      std::printf(
          "%17s problems: DOF maps %.3f, distribution %.3f, geometry %.3f, matrices %.3f, other %.3f s\n", "",
          pp.dof_map, pp.distribution, pp.geometry, pp.matrix, pp.other);
      // What AMG does not pay: the finest level's problem and assembly (shared by all three).
      const double beyond_fine = t.setup() - t.finest_problem - t.finest_assembly;
      std::printf("%17s MG set-up beyond the finest problem + assembly: %.3f s (+ solve %.3f s = %.3f s)\n",
                  "", beyond_fine, rep.linear.solve_seconds, beyond_fine + rep.linear.solve_seconds);
      std::fflush(stdout);
    }
  }
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_multigrid_levels: %s\n", e.what());
    return 1;
  }
}
