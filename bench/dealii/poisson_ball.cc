// deal.II peer of warpfem's Poisson benchmarks (benchmark only; never part of
// warpfem's build unless WARPFEM_BENCH_DEALII=ON): Q_k Poisson −Δu = 1, u = 0
// on the boundary of the unit ball (3D) or disk (2D), CG to 1e-8 relative
// preconditioned by deal.II's matrix-based geometric multigrid as in step-16
// (level matrices assembled on every level, MGTransferPrebuilt, a Householder
// coarse solve) with the smoother warpfem uses by default: Chebyshev of
// degree 2 on Jacobi over [λmax/11, λmax] (λmax from 10 CG steps), one
// V-cycle per CG step. Cells are curved by the ball's manifold through
// MappingQ of the element's degree (MappingQ1 for Q1). One process, one
// thread. Every phase is reported in wall and process CPU seconds, and the
// peak resident memory per DOF at the end; then, untimed, the L2 and
// H1-seminorm errors against the exact u = (1 − |x|²)/(2 dim) (QGauss(k + 2)),
// for a check against warpfem's solution of the same problem.
//
//   dealii_poisson_ball [refinements = 5] [ball = balanced|plain] [dim = 3] [degree = 1] [output.vtu]
//
// 3D balanced: GridGenerator::hyper_ball_balanced (32 coarse cells; 5
// refinements give 1.06 M Q1 DOFs); plain: GridGenerator::hyper_ball (7 cells;
// 5: 0.24 M, 6: 1.9 M). 2D (either): hyper_ball, 5 cells; Q1 with 9
// refinements and Q2 with 8 give 1.31 M DOFs. With an output file the
// solution is written as VTU (curved Lagrange cells for Q2), timed as a phase.

#include <deal.II/base/function.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
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
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>
#include <deal.II/numerics/vector_tools_integrate_difference.h>
#include <sys/resource.h>
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

using namespace dealii;

namespace {
/// u = (1 − |x|²)/(2 dim) solves −Δu = 1 in the unit ball with u = 0 on the sphere.
template <int dim>
class ExactSolution final : public Function<dim> {
 public:
  double value(const Point<dim>& x, const unsigned int = 0) const override {
    return (1 - x.square()) / (2 * dim);
  }
  Tensor<1, dim> gradient(const Point<dim>& x, const unsigned int = 0) const override { return -x / dim; }
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

template <int dim>
int run(unsigned int refinements, const std::string& ball, unsigned int degree, const std::string& output) {
  Phases phases;

  Triangulation<dim> tria(Triangulation<dim>::limit_level_difference_at_vertices);
  if (ball == "plain" || dim == 2)
    GridGenerator::hyper_ball(tria);
  else
    GridGenerator::hyper_ball_balanced(tria);
  tria.refine_global(refinements);
  phases.done("mesh (ball, refinements)");

  const FE_Q<dim> fe(degree);
  const MappingQ<dim> mapping(degree);
  DoFHandler<dim> dof(tria);
  dof.distribute_dofs(fe);
  dof.distribute_mg_dofs();
  phases.done("DOFs (active and levels)");

  AffineConstraints<double> constraints;
  DoFTools::make_hanging_node_constraints(dof, constraints);
  VectorTools::interpolate_boundary_values(mapping, dof, 0, Functions::ZeroFunction<dim>(), constraints);
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

  // Element matrices and loads with QGauss(k + 1), the manifold's curved
  // geometry through MappingQ(k) of the refined (curved-placed) vertices.
  const QGauss<dim> quadrature(degree + 1);
  const unsigned int n = fe.n_dofs_per_cell(), nq = quadrature.size();
  FullMatrix<double> ke(n, n);
  Vector<double> fe_load(n);
  std::vector<types::global_dof_index> indices(n);
  {
    FEValues<dim> values(mapping, fe, quadrature, update_gradients | update_values | update_JxW_values);
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
    FEValues<dim> values(mapping, fe, quadrature, update_gradients | update_JxW_values);
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
  if (!output.empty()) {
    DataOut<dim> data_out;
    DataOutBase::VtkFlags flags;
    flags.write_higher_order_cells = degree > 1;
    data_out.set_flags(flags);
    data_out.attach_dof_handler(dof);
    data_out.add_data_vector(u, "u");
    data_out.build_patches(mapping, degree, DataOut<dim>::curved_inner_cells);
    std::ofstream file(output);
    data_out.write_vtu(file);
    if (!file) {
      std::fprintf(stderr, "cannot write %s\n", output.c_str());
      return 1;
    }
    phases.done("output (VTU)");
  }
  phases.total("total");

  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double peak = static_cast<double>(usage.ru_maxrss) * 1024.0;
  std::printf(
      "deal.II %s: %dD Q%u, %s ball, %u refinements, %u levels, %u cells, %u DOFs, %u CG its; peak RSS %.0f "
      "MB (%.0f bytes/DOF); max u %.6e\n",
      DEAL_II_PACKAGE_VERSION, dim, degree, dim == 2 ? "plain" : ball.c_str(), refinements, levels,
      tria.n_active_cells(), static_cast<unsigned int>(dof.n_dofs()), control.last_step(), peak / 1048576.0,
      peak / static_cast<double>(dof.n_dofs()), u.linfty_norm());
  Vector<double> cell_errors(tria.n_active_cells());
  const ExactSolution<dim> exact;
  const QGauss<dim> error_quadrature(degree + 2);
  VectorTools::integrate_difference(mapping, dof, u, exact, cell_errors, error_quadrature,
                                    VectorTools::L2_norm);
  const double l2 = VectorTools::compute_global_error(tria, cell_errors, VectorTools::L2_norm);
  VectorTools::integrate_difference(mapping, dof, u, exact, cell_errors, error_quadrature,
                                    VectorTools::H1_seminorm);
  const double h1 = VectorTools::compute_global_error(tria, cell_errors, VectorTools::H1_seminorm);
  std::printf("L2 error %.4e, H1-seminorm error %.4e against (1 - |x|^2)/(2 dim) (untimed)\n", l2, h1);
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  const unsigned int refinements = argc > 1 ? static_cast<unsigned int>(std::atoi(argv[1])) : 5;
  const std::string ball = argc > 2 ? argv[2] : "balanced";
  const int dim = argc > 3 ? std::atoi(argv[3]) : 3;
  const int degree = argc > 4 ? std::atoi(argv[4]) : 1;
  const std::string output = argc > 5 ? argv[5] : "";
  if ((dim != 2 && dim != 3) || degree < 1 || degree > 4) {
    std::fprintf(
        stderr,
        "usage: dealii_poisson_ball [refinements] [balanced|plain] [dim 2|3] [degree 1..4] [output.vtu]\n");
    return 2;
  }
  return dim == 2 ? run<2>(refinements, ball, static_cast<unsigned int>(degree), output)
                  : run<3>(refinements, ball, static_cast<unsigned int>(degree), output);
}
