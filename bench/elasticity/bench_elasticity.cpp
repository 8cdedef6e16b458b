// Elasticity timings, printed as Markdown tables:
//  1. quasi-static neo-Hookean cantilever on a warped Q2 mesh (~100k DOFs by default):
//     Newton iterations and wall time per load step, plus the cost of one residual,
//     one Jacobian assembly and one linear solve;
//  2. the gear example (examples/gear_transient.json) end to end, without output.
//
// Run:  build/bench/elasticity/bench_elasticity [cells per side, default 112] [PETSc options]
//       mpiexec -n 2 build/bench/elasticity/bench_elasticity
// Linear solver: MUMPS LU by default; try -elasticity_ksp_type cg -elasticity_pc_type gamg.

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "apps/run.hpp"
#include "core/environment.hpp"
#include "core/log.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "mapping/make_map.hpp"

using namespace warpfem;

namespace {

void cantilever(int cells) {
  const int rank = Environment::rank();
  const Polygon source({Point<2>(0, 0), Point<2>(4, 0), Point<2>(4, 1), Point<2>(0, 1)}, "beam");
  const Polygon target({Point<2>(0, 0), Point<2>(4, 0.3), Point<2>(4.1, 1.1), Point<2>(0, 1)}, "warped beam");
  mapping::MapSpec spec;
  spec.type = "barycentric";
  spec.source = source;
  spec.target = target;
  const auto map = mapping::make_map(spec);
  const warpfem::Mesh<2> mesh =
      warpfem::structured_mesh(source, 2 * cells, cells / 2, warpfem::CellType::quadrilateral);
  fem::ElasticityData<2> data;
  data.material = fem::Material::from_young_poisson(fem::MaterialModel::neo_hookean, 1000.0, 0.3);
  const fem::ScalarFunction<2> zero = [](const Point<2>&, double) { return 0.0; };
  data.dirichlet.push_back({{3}, {zero, zero}});
  data.neumann.push_back({{1}, [](const Point<2>&, double) { return Point<2>(0.0, -10.0); }});
  Stopwatch watch;
  const fem::HyperelasticOperator op(PETSC_COMM_WORLD, mesh, map, 2, 0, data);
  const double setup = watch.seconds();
  petsc::Vector u = op.space().create_vector(), r = op.space().create_vector();
  petsc::Matrix J = op.space().create_matrix("elasticity_");

  // Kernel costs at u = 0 (averaged over 3 calls).
  watch.reset();
  for (int i = 0; i < 3; ++i) op.residual(u.get(), nullptr, 1.0, 1.0, r.get());
  const double t_residual = watch.seconds() / 3;
  watch.reset();
  for (int i = 0; i < 3; ++i) op.jacobian(u.get(), 0.0, J.get());
  const double t_jacobian = watch.seconds() / 3;

  fem::NewtonOptions newton;
  newton.log_iterations = false;
  fem::QuasiStaticSolver solver(op, newton, {.steps = 4});
  watch.reset();
  const auto report = solver.solve(u.get());
  const double total = watch.seconds();
  if (rank == 0) {
    std::printf("\n### Quasi-static neo-Hookean cantilever, Q2 on a warped %d x %d quad mesh\n\n", 2 * cells,
                cells / 2);
    std::printf("%lld DOFs on %d rank(s); operator set-up (DOF maps, partition, WarpedGeometry) %.3f s\n",
                static_cast<long long>(op.space().num_global()), Environment::size(), setup);
    std::printf("one residual %.3f s, one Jacobian assembly %.3f s\n\n", t_residual, t_jacobian);
    std::printf("| load step | s | Newton iterations | time [s] | final |R| |\n|---|---|---|---|---|\n");
    for (std::size_t k = 0; k < report.steps.size(); ++k) {
      const auto& s = report.steps[k];
      std::printf("| %zu | %.3f | %d | %.3f | %.2e |\n", k + 1, s.load, s.iterations, s.seconds,
                  s.residuals.back());
    }
    std::printf("\ntotal %.3f s, %d Newton iterations (%.3f s per iteration), %d rejected steps\n", total,
                report.newton_iterations(), total / report.newton_iterations(), report.rejected_steps);
  }
}

void gear() {
  const std::string path = std::string(WARPFEM_SOURCE_DIR) + "/examples/gear_transient.json";
  std::ifstream in(path);
  nlohmann::json json = nlohmann::json::parse(in, nullptr, true, true);
  json["verbosity"] = "warning";
  const auto cfg = io::parse_elasticity_config(json, path);
  Stopwatch watch;
  const auto result = apps::run(cfg, PETSC_COMM_WORLD, {.write_output = false});
  const double total = watch.seconds();
  if (Environment::rank() == 0) {
    std::printf("\n### Gear example (examples/gear_transient.json, no output)\n\n");
    std::printf("| DOFs | time steps | Newton iterations | solve [s] | total incl. map + mesh [s] |\n");
    std::printf("|---|---|---|---|---|\n| %lld | %d | %d | %.2f | %.2f |\n",
                static_cast<long long>(result.num_dofs), result.time_steps, result.newton_iterations,
                result.solve_seconds, total);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Environment env(argc, argv);
  log::set_level(log::Level::warning);
  const int cells = argc > 1 && argv[1][0] != '-' ? std::atoi(argv[1]) : 112;
  try {
    cantilever(cells);
    gear();
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
