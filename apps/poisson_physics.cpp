// Poisson in the run recipe: −Δu = g on the warped domain, one linear solve —
// CG preconditioned by geometric multigrid on the nested hierarchy (default),
// or the configured KSP on the finest mesh alone.

#include <petscvec.h>

#include <cmath>
#include <iomanip>

#include "apps/physics.hpp"
#include "apps/run_output.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/timer.hpp"
#include "fem/physics/poisson.hpp"
#include "io/expression.hpp"
#include "multigrid/poisson_multigrid.hpp"

namespace warpfem::apps {
namespace {

template <int dim>
class PoissonPhysics final : public Physics<dim> {
 public:
  PoissonPhysics(const io::PoissonRunConfig<dim>& cfg, MPI_Comm comm, const RunOptions& options)
      : cfg_(cfg), comm_(comm), options_(options) {}

  const fem::Problem<dim>& set_up(Mesh<dim> coarse, int refinements, mapping::MapPtr<dim> map) override {
    fem::PoissonData<dim> data;
    data.source = io::expression_function<dim>(cfg_.poisson.source, cfg_.file, "/problem/source");
    data.dirichlet = io::make_boundary_conditions<dim>(cfg_.poisson.dirichlet, cfg_.file);
    data.neumann = io::make_boundary_conditions<dim>(cfg_.poisson.neumann, cfg_.file);
    if constexpr (dim == 2) data.boundary_polygon = *cfg_.map.source;
    const int order = cfg_.poisson.order;
    const int qdeg = cfg_.poisson.quadrature_degree > 0 ? cfg_.poisson.quadrature_degree
                                                        : warpfem::default_quadrature_degree(order);
    const fem::GeometryStorage storage =
        cfg_.poisson.geometry == "streamed" ? fem::GeometryStorage::streamed : fem::GeometryStorage::cached;
    Stopwatch watch;
    const double cpu = process_cpu_seconds();
    if (use_multigrid()) {  // builds the (partitioned) hierarchy and assembles every level
      multigrid::PoissonMultigridOptions mg_options;
      mg_options.linear = cfg_.solver.linear;
      mg_options.multigrid = cfg_.solver.multigrid;
      mg_options.finest_geometry = storage;
      mg_ = std::make_unique<multigrid::PoissonMultigridSolver<dim>>(comm_, std::move(coarse), refinements,
                                                                     map, order, qdeg, data, mg_options);
    } else {
      mesh_ = std::make_unique<Mesh<dim>>(std::move(coarse));
      for (int r = 0; r < refinements; ++r) *mesh_ = warpfem::refine_uniformly(*mesh_).mesh;
      single_ = std::make_unique<fem::PoissonProblem<dim>>(comm_, *mesh_, map, order, qdeg, data, storage);
      single_->assemble();
    }
    const fem::PoissonProblem<dim>& p = problem();
    int size = 1;
    MPI_Comm_size(comm_, &size);
    const bool simplex =
        p.mesh().cell_type == CellType::triangle || p.mesh().cell_type == CellType::tetrahedron;
    log::info("assembled ", simplex ? "P" : "Q", order, " Poisson", mg_ ? " on every level" : "", ": ",
              p.dofs().num_dofs(), " DOFs on ", size, " rank(s), ",
              p.geometry().num_cells() * p.geometry().points_per_cell(),
              " warped quadrature points on rank 0 (", format_seconds(watch.seconds()), ", CPU ",
              format_seconds(process_cpu_seconds() - cpu), ")");
    check_load_is_finite();
    return p;
  }
  int order() const override { return cfg_.poisson.order; }

  void solve(RunOutput<dim>*, RunResult& result) override {
    std::string levels;
    if (mg_) {
      const auto report = mg_->solve();
      const multigrid::MultigridTimings& t = report.timings;
      log::debug("multigrid set-up: hierarchy ", format_seconds(t.hierarchy), ", problems ",
                 format_seconds(t.problems), " (geometry ", format_seconds(t.problem_parts.geometry),
                 ", DOFs ", format_seconds(t.problem_parts.dof_map + t.problem_parts.distribution),
                 ", matrices ", format_seconds(t.problem_parts.matrix), ", other ",
                 format_seconds(t.problem_parts.other), "), assembly ", format_seconds(t.assembly),
                 ", transfers ", format_seconds(t.transfers), ", KSPSetUp ", format_seconds(t.pc_setup));
      result.solve = report.linear;
      levels = " (" + std::to_string(report.levels) + " levels)";
      for (const auto& level : mg_->hierarchy().levels) result.partial_levels += level.partial ? 1 : 0;
      std::string dofs;
      for (const Index n : report.level_dofs) dofs += (dofs.empty() ? "" : ", ") + std::to_string(n);
      log::info("multigrid levels, coarse to fine: ", dofs, " DOFs");
    } else {
      petsc::LinearSolveOptions linear = cfg_.solver.linear;
      if (linear.pc_type == "mg") linear.pc_type = "gamg";  // one level: nothing to build a hierarchy from
      result.solve = single_->solve(linear);
    }
    result.solve_seconds = result.solve.solve_seconds;
    log::info("solved with ", result.solve.ksp_type, "/", result.solve.pc_type, levels, ": ",
              result.solve.iterations, " iterations, residual ", std::scientific, std::setprecision(2),
              result.solve.residual_norm, " (setup ", format_seconds(result.solve.setup_seconds), ", solve ",
              format_seconds(result.solve.solve_seconds), ")");
  }

  void report(RunResult& result) const override {
    const fem::PoissonProblem<dim>& p = problem();
    result.area = p.area();
    if (!cfg_.poisson.exact_solution.empty()) {
      const io::Expression exact(cfg_.poisson.exact_solution, cfg_.file, "/problem/exact_solution");
      const fem::GradientFunction<dim> grad = [&exact](const Point<dim>& x, double t) {
        return exact.template gradient<dim>(x, t);
      };
      const fem::ScalarFunction<dim> value = [&exact](const Point<dim>& x, double t) {
        return exact.template at<dim>(x, t);
      };
      const auto e = p.errors(value, grad);
      result.l2_error = e.l2;
      result.h1_error = e.h1_semi;
      log::info("error against exact solution: L2 ", std::scientific, std::setprecision(4), e.l2,
                ", H1-seminorm ", e.h1_semi);
    }
    if (options_.gather_solution) result.solution = p.distribution().gather_all(p.solution());
  }

  void release_solver() override {
    if (mg_)
      mg_->release_solver();
    else
      single_->release_operator();
  }

  Vec state() const override { return problem().solution(); }
  void add_fields(const fem::OutputMesh<dim>& mesh, Vec u, io::VtkOutput<dim>& vtk) const override {
    const fem::PoissonProblem<dim>& p = problem();
    vtk.point_fields.push_back(
        {"u", 1, mesh.interpolate(p.dofs(), p.distribution(), p.distribution().gather_relevant(u))});
  }

 private:
  /// Geometric multigrid needs at least one refinement; one level is solved with
  /// the configured (or an algebraic) preconditioner.
  bool use_multigrid() const { return cfg_.solver.linear.pc_type == "mg" && cfg_.mesh.refinements > 0; }
  const fem::PoissonProblem<dim>& problem() const { return mg_ ? mg_->finest() : *single_; }

  /// A NaN or inf load would only surface as a diverging multigrid smoother.
  void check_load_is_finite() const {
    PetscReal rhs_norm = 0;
    PetscCallAbort(comm_, VecNorm(problem().rhs(), NORM_INFINITY, &rhs_norm));
    if (!std::isfinite(rhs_norm))
      throw Error(
          "the assembled load vector contains NaN or inf: the source term (or a boundary value) is not "
          "finite somewhere in the domain",
          {.file = cfg_.file,
           .key_path = "/problem/source",
           .hint = "check /problem/source, /problem/dirichlet and /problem/neumann for division by zero "
                   "or sqrt/log of negative values on the target domain"});
  }

  const io::PoissonRunConfig<dim>& cfg_;
  MPI_Comm comm_;
  RunOptions options_;
  std::unique_ptr<multigrid::PoissonMultigridSolver<dim>> mg_;
  std::unique_ptr<Mesh<dim>> mesh_;
  std::unique_ptr<fem::PoissonProblem<dim>> single_;
};

}  // namespace

template <int dim>
std::unique_ptr<Physics<dim>> make_physics(const io::PoissonRunConfig<dim>& config, MPI_Comm comm,
                                           const RunOptions& options) {
  return std::make_unique<PoissonPhysics<dim>>(config, comm, options);
}

template std::unique_ptr<Physics<2>> make_physics(const io::PoissonRunConfig<2>&, MPI_Comm,
                                                  const RunOptions&);
template std::unique_ptr<Physics<3>> make_physics(const io::PoissonRunConfig<3>&, MPI_Comm,
                                                  const RunOptions&);

}  // namespace warpfem::apps
