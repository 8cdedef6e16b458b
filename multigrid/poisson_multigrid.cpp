#include "multigrid/poisson_multigrid.hpp"

#include <time.h>

#include <optional>

#include "core/collective_error.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"

namespace warpfem::multigrid {
namespace {
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// The hierarchy partitioned for `comm`'s ranks; with `partial_levels` the
/// levels above the base are built only around this rank's cells
/// (fem/partial_refinement.hpp; elements with edge DOFs get whole levels on a
/// nested partition).
template <int dim>
fem::MeshHierarchy<dim> timed_hierarchy(MPI_Comm comm, warpfem::Mesh<dim> coarse, int refinements,
                                        bool partial_levels, Index base_cells_per_part, double& seconds) {
  if (refinements < 0)
    throw Error("multigrid: negative number of refinements " + std::to_string(refinements),
                {.file = "", .key_path = "mesh.refinements", .hint = "use 0 or more refinements"});
  Stopwatch watch;
  fem::HierarchyPartition partition;
  MPI_Comm_size(comm, &partition.parts);
  MPI_Comm_rank(comm, &partition.rank);
  partition.partial_levels = partial_levels;
  partition.min_cells_per_part = base_cells_per_part;
  // Each rank refines its own levels: a failure there must end every rank.
  std::optional<fem::MeshHierarchy<dim>> h;
  run_collectively(comm, [&] { h.emplace(std::move(coarse), refinements, partition); });
  seconds = watch.seconds();
  return std::move(*h);
}
}  // namespace

template <int dim>
PoissonMultigridSolver<dim>::PoissonMultigridSolver(MPI_Comm comm, warpfem::Mesh<dim> coarse, int refinements,
                                                    mapping::MapPtr<dim> map, int order,
                                                    int quadrature_degree, fem::PoissonData<dim> data,
                                                    const PoissonMultigridOptions& options)
    : hierarchy_(timed_hierarchy(comm, std::move(coarse), refinements, options.partial_levels && order == 1,
                                 options.base_cells_per_part, timings_.hierarchy)) {
  Stopwatch watch;
  MultigridTimings& t = timings_;
  const int levels = hierarchy_.num_levels();
  const bool smoothed = options.multigrid.prolongation == MultigridSettings::Prolongation::smoothed;
  // Smoothed prolongations bring their own Galerkin operators: only the finest level is assembled.
  const bool galerkin =
      smoothed || options.multigrid.coarse_operators == MultigridSettings::CoarseOperators::galerkin;
  report_.levels = levels;

  // 1. One PoissonProblem (DOF map, distribution, warped geometry) per level, on a
  // nested cell partition. The coarse levels' operators are assembled once: their
  // geometry is streamed.
  watch.reset();
  const std::vector<fem::LevelPartition>& partitions = hierarchy_.partitions;
  for (int l = 0; l < levels; ++l) {
    const fem::GeometryStorage storage =
        l == levels - 1 ? options.finest_geometry : fem::GeometryStorage::streamed;
    const warpfem::Mesh<dim>& mesh = hierarchy_.levels[static_cast<std::size_t>(l)];
    const double cpu_before = process_cpu_seconds();
    if (partitions.empty()) {  // not built for a partition: each level partitioned on its own
      problems_.push_back(std::make_unique<fem::PoissonProblem<dim>>(comm, mesh, map, order,
                                                                     quadrature_degree, data, storage));
    } else {
      const fem::LevelPartition& part = partitions[static_cast<std::size_t>(l)];
      problems_.push_back(
          part.blocks ? std::make_unique<fem::PoissonProblem<dim>>(comm, mesh, map, order, quadrature_degree,
                                                                   data, storage, *part.blocks)
                      : std::make_unique<fem::PoissonProblem<dim>>(comm, mesh, map, order, quadrature_degree,
                                                                   data, storage, part.cell_owner));
    }
    report_.level_dofs.push_back(problems_.back()->dofs().num_dofs());
    const fem::PoissonSetupTimings& p = problems_.back()->setup_timings();
    t.problem_parts.dof_map += p.dof_map;
    t.problem_parts.distribution += p.distribution;
    t.problem_parts.geometry += p.geometry;
    t.problem_parts.matrix += p.matrix;
    t.problem_parts.other += p.other;
    if (l == levels - 1) t.finest_problem = p.total(), t.finest_cpu = process_cpu_seconds() - cpu_before;
  }
  t.problems = watch.seconds();

  // 2. Level operators: rediscretization on every level, or the finest only (Galerkin).
  watch.reset();
  for (int l = galerkin ? levels - 1 : 0; l < levels; ++l) {
    Stopwatch level_watch;
    const double cpu_before = process_cpu_seconds();
    problems_[l]->assemble();
    if (l == levels - 1)
      t.finest_assembly = level_watch.seconds(), t.finest_cpu += process_cpu_seconds() - cpu_before;
  }
  t.assembly = watch.seconds();

  // 3. Prolongations, consistent with the eliminated Dirichlet rows and columns.
  watch.reset();
  std::vector<const fem::Problem<dim>*> level_problems;
  for (const auto& p : problems_) level_problems.push_back(p.get());
  multigrid_ = std::make_unique<GeometricMultigrid<dim>>(hierarchy_, level_problems, options.multigrid);
  if (smoothed) multigrid_->smooth(problems_.back()->matrix());
  t.transfers = watch.seconds();

  // 4. KSP + PCMG; the options database overrides every default.
  watch.reset();
  std::vector<Mat> operators;
  for (int l = galerkin ? levels - 1 : 0; l < levels; ++l) operators.push_back(problems_[l]->matrix());
  const petsc::LinearSolveOptions& lin = options.linear;
  WARPFEM_PETSC_CHECK(KSPCreate(comm, ksp_.out()));
  if (!lin.prefix.empty()) WARPFEM_PETSC_CHECK(KSPSetOptionsPrefix(ksp_.get(), lin.prefix.c_str()));
  WARPFEM_PETSC_CHECK(KSPSetType(ksp_.get(), lin.ksp_type.c_str()));
  WARPFEM_PETSC_CHECK(KSPSetNormType(ksp_.get(), KSP_NORM_UNPRECONDITIONED));
  WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp_.get(), lin.rtol, lin.atol, PETSC_DEFAULT, lin.max_iterations));
  WARPFEM_PETSC_CHECK(KSPSetInitialGuessNonzero(ksp_.get(), PETSC_TRUE));
  multigrid_->configure(ksp_.get(), operators);
  WARPFEM_PETSC_CHECK(KSPSetFromOptions(ksp_.get()));
  reconcile_chebyshev_bounds(ksp_.get(), multigrid_->settings());
  WARPFEM_PETSC_CHECK(KSPSetUp(ksp_.get()));
  t.pc_setup = watch.seconds();
}

template <int dim>
PoissonMultigridSolver<dim>::~PoissonMultigridSolver() = default;

template <int dim>
MultigridSolveReport PoissonMultigridSolver<dim>::solve() {
  fem::PoissonProblem<dim>& p = finest();
  Stopwatch watch;
  // A zero initial guess spares CG the product A·0 for its first residual.
  PetscReal largest = 0;
  WARPFEM_PETSC_CHECK(VecNorm(p.solution(), NORM_INFINITY, &largest));
  WARPFEM_PETSC_CHECK(KSPSetInitialGuessNonzero(ksp_.get(), largest > 0 ? PETSC_TRUE : PETSC_FALSE));
  WARPFEM_PETSC_CHECK(KSPSolve(ksp_.get(), p.rhs(), p.solution()));
  petsc::LinearSolveReport& r = report_.linear;
  r.solve_seconds = watch.seconds();
  report_.timings = timings_;
  r.setup_seconds = timings_.setup();
  petsc::collect_solve_outcome(ksp_.get(), r);
  petsc::throw_if_diverged(r, "multigrid-preconditioned " + r.ksp_type,
                           "check the level operators with -ksp_view, try -mg_levels_ksp_type richardson "
                           "-mg_levels_pc_type sor, or raise solver.max_iterations");
  return report_;
}

template class PoissonMultigridSolver<2>;
template class PoissonMultigridSolver<3>;

}  // namespace warpfem::multigrid
