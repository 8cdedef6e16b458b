// deal.II peer of bench_poisson_3d (benchmark only; never part of warpfem's
// build unless WARPFEM_BENCH_DEALII=ON): Q1 Poisson −Δu = 1, u = 0 on the
// boundary of a 3D ball, CG to 1e-8 relative preconditioned by deal.II's
// matrix-based geometric multigrid as in step-16 (level matrices assembled on
// every level, MGTransferPrebuilt, a Householder coarse solve) with the
// smoother warpfem uses by default: Chebyshev of degree 2 on Jacobi over
// [λmax/11, λmax] (λmax from 10 CG steps), one V-cycle per CG step. One
// process, one thread. Every phase is reported in wall and process CPU
// seconds, and the peak resident memory per DOF at the end; then, untimed,
// the L2 and H1-seminorm errors against the exact u = (1 − |x|²)/6 (QGauss(3),
// MappingQ1 as in the assembly), for a check against warpfem's solution of
// the same problem (bench_poisson_3d -domain ball).
//
//   dealii_poisson_ball [refinements = 5] [ball = balanced|plain]
//
// balanced: GridGenerator::hyper_ball_balanced (32 coarse cells; 5 refinements
// give 1.06 M DOFs); plain: GridGenerator::hyper_ball (7 cells; 5: 0.24 M,
// 6: 1.9 M).

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>
#include <deal.II/multigrid/mg_coarse.h>
#include <deal.II/multigrid/mg_constrained_dofs.h>
#include <deal.II/multigrid/mg_matrix.h>
#include <deal.II/multigrid/mg_smoother.h>
#include <deal.II/multigrid/mg_tools.h>
#include <deal.II/multigrid/mg_transfer.h>
#include <deal.II/multigrid/multigrid.h>
#include <deal.II/numerics/vector_tools.h>
#include <deal.II/numerics/vector_tools_integrate_difference.h>
#include <sys/resource.h>
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace dealii;

namespace {
constexpr int dim = 3;

/// u = (1 − |x|²)/6 solves −Δu = 1 in the unit ball with u = 0 on the sphere.
class ExactSolution final : public Function<dim> {
 public:
  double value(const Point<dim>& x, const unsigned int = 0) const override { return (1 - x.square()) / 6; }
  Tensor<1, dim> gradient(const Point<dim>& x, const unsigned int = 0) const override { return -x / 3; }
};

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Wall and CPU seconds of consecutive phases.
class Phases {
 public:
  void done(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    const double cpu = cpu_seconds();
    const double wall = std::chrono::duration<double>(now - wall_).count(), c = cpu - cpu_;
    total_wall_ += wall, total_cpu_ += c;
    std::printf("  %-28s %8.3f s (CPU %.3f s)\n", name, wall, c);
    wall_ = now, cpu_ = cpu;
  }
  void total(const char* name) const {
    std::printf("  %-28s %8.3f s (CPU %.3f s)\n", name, total_wall_, total_cpu_);
  }

 private:
  std::chrono::steady_clock::time_point wall_ = std::chrono::steady_clock::now();
  double cpu_ = cpu_seconds(), total_wall_ = 0, total_cpu_ = 0;
};
}  // namespace

int main(int argc, char** argv) {
  const unsigned int refinements = argc > 1 ? static_cast<unsigned int>(std::atoi(argv[1])) : 5;
  const std::string ball = argc > 2 ? argv[2] : "balanced";
  Phases phases;

  Triangulation<dim> tria(Triangulation<dim>::limit_level_difference_at_vertices);
  if (ball == "plain")
    GridGenerator::hyper_ball(tria);
  else
    GridGenerator::hyper_ball_balanced(tria);
  tria.refine_global(refinements);
  phases.done("mesh (ball, refinements)");

  const FE_Q<dim> fe(1);
  DoFHandler<dim> dof(tria);
  dof.distribute_dofs(fe);
  dof.distribute_mg_dofs();
  phases.done("DOFs (active and levels)");

  AffineConstraints<double> constraints;
  DoFTools::make_hanging_node_constraints(dof, constraints);
  VectorTools::interpolate_boundary_values(dof, 0, Functions::ZeroFunction<dim>(), constraints);
  constraints.close();
  SparsityPattern pattern;
  {
    DynamicSparsityPattern dsp(dof.n_dofs());
    DoFTools::make_sparsity_pattern(dof, dsp, constraints, false);
    pattern.copy_from(dsp);
  }
  SparseMatrix<double> A(pattern);
  Vector<double> u(dof.n_dofs()), b(dof.n_dofs());

  const unsigned int levels = tria.n_global_levels();
  MGConstrainedDoFs mg_constrained;
  mg_constrained.initialize(dof);
  mg_constrained.make_zero_boundary_constraints(dof, {types::boundary_id(0)});
  MGLevelObject<SparsityPattern> level_patterns(0, levels - 1);
  MGLevelObject<SparseMatrix<double>> level_matrices(0, levels - 1);
  std::vector<AffineConstraints<double>> level_constraints(levels);
  for (unsigned int l = 0; l < levels; ++l) {
    DynamicSparsityPattern dsp(dof.n_dofs(l), dof.n_dofs(l));
    MGTools::make_sparsity_pattern(dof, dsp, l);
    level_patterns[l].copy_from(dsp);
    level_matrices[l].reinit(level_patterns[l]);
    IndexSet relevant;
    DoFTools::extract_locally_relevant_level_dofs(dof, l, relevant);
    level_constraints[l].reinit(relevant);
    level_constraints[l].add_lines(mg_constrained.get_boundary_indices(l));
    level_constraints[l].close();
  }
  phases.done("constraints, sparsity");

  // Element matrices and loads with QGauss(2) (8 points), the manifold's
  // curved geometry through MappingQ1 of the refined (curved-placed) vertices.
  const QGauss<dim> quadrature(2);
  const unsigned int n = fe.n_dofs_per_cell(), nq = quadrature.size();
  FullMatrix<double> ke(n, n);
  Vector<double> fe_load(n);
  std::vector<types::global_dof_index> indices(n);
  {
    FEValues<dim> values(fe, quadrature, update_gradients | update_values | update_JxW_values);
    for (const auto& cell : dof.active_cell_iterators()) {
      values.reinit(cell);
      ke = 0;
      fe_load = 0;
      for (unsigned int q = 0; q < nq; ++q) {
        const double w = values.JxW(q);
        for (unsigned int i = 0; i < n; ++i) {
          for (unsigned int j = 0; j < n; ++j)
            ke(i, j) += values.shape_grad(i, q) * values.shape_grad(j, q) * w;
          fe_load(i) += values.shape_value(i, q) * w;
        }
      }
      cell->get_dof_indices(indices);
      constraints.distribute_local_to_global(ke, fe_load, indices, A, b);
    }
  }
  phases.done("assembly (finest)");
  {
    FEValues<dim> values(fe, quadrature, update_gradients | update_JxW_values);
    for (const auto& cell : dof.mg_cell_iterators()) {
      values.reinit(cell);
      ke = 0;
      for (unsigned int q = 0; q < nq; ++q) {
        const double w = values.JxW(q);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            ke(i, j) += values.shape_grad(i, q) * values.shape_grad(j, q) * w;
      }
      cell->get_mg_dof_indices(indices);
      level_constraints[cell->level()].distribute_local_to_global(ke, indices, level_matrices[cell->level()]);
    }
  }
  phases.done("assembly (levels)");

  MGTransferPrebuilt<Vector<double>> transfer(mg_constrained);
  transfer.build(dof);
  FullMatrix<double> coarse;
  coarse.copy_from(level_matrices[0]);
  MGCoarseGridHouseholder<double, Vector<double>> coarse_solver;
  coarse_solver.initialize(coarse);
  using Smoother = PreconditionChebyshev<SparseMatrix<double>, Vector<double>>;
  mg::SmootherRelaxation<Smoother, Vector<double>> smoother;
  MGLevelObject<Smoother::AdditionalData> smoother_data(0, levels - 1);
  for (unsigned int l = 0; l < levels; ++l) {
    smoother_data[l].degree = 2;
    smoother_data[l].smoothing_range = 11.;  // [λmax/11, λmax], warpfem's [0.1, 1.1]·λmax
    smoother_data[l].eig_cg_n_iterations = 10;
  }
  smoother.initialize(level_matrices, smoother_data);
  mg::Matrix<Vector<double>> mg_matrix(level_matrices);
  Multigrid<Vector<double>> mg(mg_matrix, coarse_solver, transfer, smoother, smoother);
  PreconditionMG<dim, Vector<double>, MGTransferPrebuilt<Vector<double>>> preconditioner(dof, mg, transfer);
  phases.done("multigrid set-up");

  SolverControl control(1000, 1e-8 * b.l2_norm());
  SolverCG<Vector<double>> cg(control);
  cg.solve(A, u, b, preconditioner);
  constraints.distribute(u);
  phases.done("CG solve");
  phases.total("total");

  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double peak = static_cast<double>(usage.ru_maxrss) * 1024.0;
  std::printf(
      "deal.II %s: %s ball, %u refinements, %u levels, %u cells, %u DOFs, %u CG its; peak RSS %.0f MB "
      "(%.0f bytes/DOF); max u %.6e\n",
      DEAL_II_PACKAGE_VERSION, ball.c_str(), refinements, levels, tria.n_active_cells(),
      static_cast<unsigned int>(dof.n_dofs()), control.last_step(), peak / 1048576.0,
      peak / static_cast<double>(dof.n_dofs()), u.linfty_norm());
  Vector<double> cell_errors(tria.n_active_cells());
  const ExactSolution exact;
  VectorTools::integrate_difference(dof, u, exact, cell_errors, QGauss<dim>(3), VectorTools::L2_norm);
  const double l2 = VectorTools::compute_global_error(tria, cell_errors, VectorTools::L2_norm);
  VectorTools::integrate_difference(dof, u, exact, cell_errors, QGauss<dim>(3), VectorTools::H1_seminorm);
  const double h1 = VectorTools::compute_global_error(tria, cell_errors, VectorTools::H1_seminorm);
  std::printf("L2 error %.4e, H1-seminorm error %.4e against (1 - |x|^2)/6 (untimed)\n", l2, h1);
  return 0;
}
