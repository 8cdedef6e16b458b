#include "apps/elasticity_stepping.hpp"

#include "apps/run_output.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"
#include "fem/physics/elasticity/quasi_static_solver.hpp"
#include "fem/physics/elasticity/transient_solver.hpp"
#include "io/expression.hpp"

namespace warpfem::apps {
namespace {

/// A solver that gives up names no config field; `key` (the load or time stepping) is
/// what the user can change, so the error is placed there.
Error at_config_key(const Error& e, const std::string& file, const std::string& key) {
  if (!e.context().file.empty() || !e.context().key_path.empty()) return e;
  return Error(e.message(), {.file = file, .key_path = key, .hint = e.context().hint});
}

/// v(x) at every owned node from the initial-velocity expressions (x = f(x0)).
template <int dim>
void interpolate_initial_velocity(const io::ElasticityRunConfig<dim>& cfg,
                                  const fem::HyperelasticOperator<dim>& op, Vec v) {
  const auto& iv = cfg.problem.initial_velocity;
  if (iv == io::zero_vector_expression<dim>()) return;
  std::vector<io::Expression> e;
  for (int c = 0; c < dim; ++c)
    e.emplace_back(iv[static_cast<std::size_t>(c)], cfg.file,
                   "/problem/initial_velocity/" + std::to_string(c));
  const auto& dist = op.space().nodes();
  std::vector<Index> owned;
  for (Index d : dist.relevant_dofs())
    if (dist.owns(d)) owned.push_back(d);
  Points<dim> x0(static_cast<Index>(owned.size()), dim);
  for (std::size_t i = 0; i < owned.size(); ++i)
    x0.row(static_cast<Index>(i)) = op.space().dofs().dof_points().row(owned[i]);
  const Points<dim> x = fem::warp_nodes(op.map(), x0);  // once, at set-up
  for (std::size_t i = 0; i < owned.size(); ++i) {
    const Point<dim> p = x.row(static_cast<Index>(i)).transpose();
    PetscInt rows[dim];
    PetscScalar vals[dim];
    for (int c = 0; c < dim; ++c) {
      rows[c] = op.space().global(owned[i], c);
      vals[c] = e[static_cast<std::size_t>(c)].template at<dim>(p, 0.0);
    }
    WARPFEM_PETSC_CHECK(VecSetValues(v, dim, rows, vals, INSERT_VALUES));
  }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(v));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(v));
}

}  // namespace

template <int dim>
void solve_quasi_static(const SteppingContext<dim>& c, Vec u, RunResult& result) {
  const io::ElasticityRunConfig<dim>& cfg = c.config;
  log::info("quasi-static: load factor 0 → 1 in ", cfg.load_stepping.steps, " step(s)");
  fem::QuasiStaticSolver solver(c.op, c.newton, {cfg.load_stepping.steps, cfg.load_stepping.min_increment});
  int index = 0;
  double last_load = 0;
  if (c.output) c.output->write_step(0, 0.0, u);
  try {
    const auto report = solver.solve(u, [&](const fem::LoadStep& step, Vec state) {
      ++index;
      last_load = step.load;
      if (c.output && (index % cfg.output.every == 0 || step.load >= 1.0))
        c.output->write_step(index, step.load, state);
    });
    result.load_steps = report.steps;
    result.rejected_steps = report.rejected_steps;
    result.newton_iterations = report.newton_iterations();
    result.domain_rejections = report.domain_rejections;
  } catch (const Error& e) {
    if (c.output && c.output->last_step() != index) c.output->write_step(index, last_load, u);
    throw at_config_key(e, cfg.file, "/load_stepping");
  }
}

template <int dim>
void solve_transient(const SteppingContext<dim>& c, Vec u, RunResult& result) {
  const io::ElasticityRunConfig<dim>& cfg = c.config;
  petsc::Vector v = c.op.space().create_vector();
  interpolate_initial_velocity(cfg, c.op, v.get());
  fem::TransientOptions t;
  t.time_step = cfg.time.step;
  t.end_time = cfg.time.end;
  t.rho_infinity = cfg.time.rho_infinity;
  t.damping = cfg.time.damping;
  t.compute_energy = c.compute_energy;
  log::info("transient: generalized-α (ρ∞ = ", t.rho_infinity, "), Δt = ", t.time_step, ", end ", t.end_time);
  fem::TransientSolver solver(c.op, t, c.newton);
  int last_step = -1;
  double last_time = 0;
  try {
    const auto report = solver.solve(u, v.get(), [&](const fem::TransientStep& s, Vec state, Vec) {
      result.history.push_back(s);
      last_step = s.step;
      last_time = s.time;
      if (c.output && (s.step % cfg.output.every == 0 || s.time >= cfg.time.end * (1 - 1e-12)))
        c.output->write_step(s.step, s.time, state);
    });
    result.time_steps = report.steps;
    result.newton_iterations = report.newton_iterations;
    result.domain_rejections = report.domain_rejections;
  } catch (const Error& e) {
    if (c.output && last_step >= 0 && c.output->last_step() != last_step)
      c.output->write_step(last_step, last_time, u);
    throw at_config_key(e, cfg.file, "/time");
  }
}

template void solve_quasi_static(const SteppingContext<2>&, Vec, RunResult&);
template void solve_quasi_static(const SteppingContext<3>&, Vec, RunResult&);
template void solve_transient(const SteppingContext<2>&, Vec, RunResult&);
template void solve_transient(const SteppingContext<3>&, Vec, RunResult&);

}  // namespace warpfem::apps
