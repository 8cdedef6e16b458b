#include "apps/elasticity_run.hpp"

#include <iomanip>
#include <memory>

#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/check.hpp"
#include "core/timer.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/elasticity/nodal_projection.hpp"
#include "fem/postprocessing/output_mesh.hpp"
#include "io/config_field.hpp"
#include "io/expression.hpp"
#include "io/pvd_writer.hpp"
#include "io/vtk_writer.hpp"
#include "mapping/make_map.hpp"
#include "multigrid/geometric_multigrid.hpp"

namespace warpfem::apps {
namespace {

/// A solver that gives up names no config field; `key` (the load or time stepping) is
/// what the user can change, so the error is placed there.
Error at_config_key(const Error& e, const std::string& file, const std::string& key) {
  if (!e.context().file.empty() || !e.context().key_path.empty()) return e;
  return Error(e.message(), {.file = file, .key_path = key, .hint = e.context().hint});
}

/// Writes numbered VTK files of the displacement, von Mises stress and det F, and the PVD index.
class ElasticityOutput {
 public:
  /// `cell_owner`: the partition the operator was built with (empty: the default).
  ElasticityOutput(const io::ElasticityConfig& cfg, const fem::HyperelasticOperator& op,
                   const warpfem::Mesh<2>& mesh, MPI_Comm comm, const std::vector<int>& cell_owner)
      : cfg_(cfg),
        op_(op),
        comm_(comm),
        projection_(comm, mesh, op.geometry(), cell_owner),
        pvd_(comm, cfg.output.directory, cfg.output.name) {
    const int order = cfg.output.vtk_order > 0 ? cfg.output.vtk_order
                                               : std::max(cfg.problem.order, op.map().is_affine() ? 1 : 2);
    mesh_ = fem::make_output_mesh(mesh, op.space().nodes(), op.map(), order);
    fem::log_untangling(comm, mesh_);
  }

  /// Writes step `index` at time (or load factor) `time`; returns the VTK file.
  std::string write(int index, double time, Vec u) {
    const VectorX ur = op_.space().gather_relevant(u);
    const VectorX ux =
        mesh_.interpolate(op_.space().dofs(), op_.space().nodes(), op_.space().component(ur, 0));
    const VectorX uy =
        mesh_.interpolate(op_.space().dofs(), op_.space().nodes(), op_.space().component(ur, 1));
    std::vector<double> disp(static_cast<std::size_t>(3 * ux.size()), 0.0);
    for (Index i = 0; i < ux.size(); ++i) {
      disp[static_cast<std::size_t>(3 * i)] = ux(i);
      disp[static_cast<std::size_t>(3 * i + 1)] = uy(i);
    }
    const auto cells = op_.point_values(u);
    const VectorX vm = mesh_.interpolate(projection_.dofs(), projection_.distribution(),
                                         projection_.project(cells.von_mises));
    const VectorX det =
        mesh_.interpolate(projection_.dofs(), projection_.distribution(), projection_.project(cells.det_F));
    io::VtkOutput<2> vtk;
    vtk.mesh = &mesh_;
    vtk.compression = io::vtk_compression(cfg_.output.compression);
    vtk.point_fields.push_back({"displacement", 3, disp});
    vtk.point_fields.push_back({"von_mises", 1, std::vector<double>(vm.data(), vm.data() + vm.size())});
    vtk.point_fields.push_back({"det_F", 1, std::vector<double>(det.data(), det.data() + det.size())});
    vtk.point_fields.push_back(
        {"det_Jf", 1,
         std::vector<double>(mesh_.map_det.data(), mesh_.map_det.data() + mesh_.map_det.size())});
    vtk.cell_fields.push_back({"det_F_min", 1, mesh_.cell_values(cells.min_det_F)});
    vtk.cell_fields.push_back({"von_mises_mean", 1, mesh_.cell_values(cells.mean_von_mises)});
    int rank = 0;
    MPI_Comm_rank(comm_, &rank);
    vtk.cell_fields.push_back(
        {"rank", 1, std::vector<double>(static_cast<std::size_t>(mesh_.cells.rows()), rank)});
    const std::string file = io::write_vtk(comm_, vtk, cfg_.output.directory, pvd_.step_name(index));
    pvd_.add(time, file);
    last_index_ = index;
    return file;
  }
  int last_index() const { return last_index_; }
  std::string pvd_path() const { return pvd_.path(); }

 private:
  const io::ElasticityConfig& cfg_;
  const fem::HyperelasticOperator& op_;
  MPI_Comm comm_;
  fem::OutputMesh<2> mesh_;
  fem::NodalProjection projection_;
  io::PvdWriter pvd_;
  int last_index_ = -1;
};

fem::NewtonOptions newton_options(const io::NewtonSpec& s) {
  fem::NewtonOptions o;
  o.rtol = s.rtol;
  o.atol = s.atol;
  o.max_iterations = s.max_iterations;
  o.ksp_type = s.ksp_type;
  o.pc_type = s.pc_type;
  o.factor_solver = s.factor_solver;
  return o;
}

double max_nodal_displacement(const fem::VectorSpace<2>& space, Vec u) {
  const PetscScalar* a = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(u, &a));
  double local = 0;
  for (PetscInt i = 0; i + 1 < space.num_owned(); i += 2) local = std::max(local, std::hypot(a[i], a[i + 1]));
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(u, &a));
  double global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, space.comm());
  return global;
}

/// v(x) at every owned node from the initial-velocity expressions (x = f(x0)).
void interpolate_initial_velocity(const io::ElasticityConfig& cfg, const fem::HyperelasticOperator& op,
                                  Vec v) {
  const auto& iv = cfg.problem.initial_velocity;
  if (iv[0] == "0" && iv[1] == "0") return;
  const io::Expression ex(iv[0], cfg.file, "/problem/initial_velocity/0");
  const io::Expression ey(iv[1], cfg.file, "/problem/initial_velocity/1");
  const auto& dist = op.space().nodes();
  std::vector<Index> owned;
  for (Index d : dist.relevant_dofs())
    if (dist.owns(d)) owned.push_back(d);
  Points<2> x0(static_cast<Index>(owned.size()), 2);
  for (std::size_t i = 0; i < owned.size(); ++i)
    x0.row(static_cast<Index>(i)) = op.space().dofs().dof_points().row(owned[i]);
  const Points<2> x = fem::warp_nodes(op.map(), x0);  // once, at set-up
  for (std::size_t i = 0; i < owned.size(); ++i) {
    const Point<2> p = x.row(static_cast<Index>(i)).transpose();
    const PetscInt rows[2] = {op.space().global(owned[i], 0), op.space().global(owned[i], 1)};
    const PetscScalar vals[2] = {ex.at<2>(p, 0.0), ey.at<2>(p, 0.0)};
    WARPFEM_PETSC_CHECK(VecSetValues(v, 2, rows, vals, INSERT_VALUES));
  }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(v));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(v));
}

}  // namespace

ElasticityRunResult run_elasticity(const io::ElasticityConfig& cfg, MPI_Comm comm,
                                   const ElasticityRunOptions& options) {
  ElasticityRunResult result;
  Stopwatch total;
  int size = 1;
  MPI_Comm_size(comm, &size);

  // 1. The map f: Ω0 → Ω1.
  Stopwatch watch;
  const mapping::MapPtr<2> map = mapping::make_map(cfg.map);
  log::info("map: ", map->describe(), " (", format_seconds(watch.seconds()), ")");

  // 2. The simple mesh of Ω0 and its uniform refinements (kept as a hierarchy for multigrid).
  watch.reset();
  const fem::MeshHierarchy<2> hierarchy(
      fem::make_coarse_mesh(*cfg.map.source, cfg.map.target ? *cfg.map.target : *cfg.map.source, *map,
                            cfg.mesh),
      cfg.mesh.refinements);
  const warpfem::Mesh<2>& mesh = hierarchy.finest();
  result.num_cells = mesh.num_cells();
  result.h = mesh.max_edge_length();
  log::info("mesh of Ω0: ", mesh.num_cells(), " ", warpfem::to_string(mesh.cell_type), "s, ",
            mesh.num_vertices(), " vertices, h = ", std::setprecision(4), result.h, " (",
            cfg.mesh.refinements, " refinements, ", format_seconds(watch.seconds()), ")");

  // 3. The hyperelastic operator on the warped mesh (f evaluated once here); with
  // multigrid on the hierarchy's nested partition, which the coarse levels share.
  watch.reset();
  fem::NewtonOptions newton = newton_options(cfg.solver);
  const std::vector<std::vector<int>> level_owners =
      newton.pc_type == "mg" ? fem::nested_partitions(hierarchy, size) : std::vector<std::vector<int>>{};
  const std::vector<int> no_owners;
  const std::vector<int>& cell_owner = level_owners.empty() ? no_owners : level_owners.back();
  const fem::HyperelasticOperator op(comm, mesh, map, cfg.problem.order, cfg.problem.quadrature_degree,
                                     io::make_elasticity_data(cfg), cell_owner);
  result.num_dofs = op.space().num_global();
  const std::string element = std::string(mesh.cell_type == warpfem::CellType::triangle ? "P" : "Q") +
                              std::to_string(cfg.problem.order);
  log::info("elasticity: ", fem::to_string(op.material().model), " (λ = ", op.material().lambda,
            ", μ = ", op.material().mu, ", ρ = ", op.material().density, "), vector ", element, ", ",
            result.num_dofs, " DOFs on ", size, " rank(s), ", op.num_constrained(), " constrained (",
            format_seconds(watch.seconds()), ")");

  std::unique_ptr<ElasticityOutput> output;
  if (options.write_output && cfg.output.vtk)
    output = std::make_unique<ElasticityOutput>(cfg, op, mesh, comm, cell_owner);
  petsc::Vector u = op.space().create_vector();
  std::unique_ptr<multigrid::GeometricMultigrid<2>> mg;
  if (newton.pc_type == "mg") {
    // Geometric multigrid on the mesh hierarchy, Galerkin coarse operators of each Newton Jacobian.
    watch.reset();
    mg = std::make_unique<multigrid::GeometricMultigrid<2>>(
        hierarchy, op, multigrid::GeometricMultigrid<2>::galerkin_defaults(), level_owners);
    if (newton.ksp_type == "preonly") newton.ksp_type = "gmres";  // one V-cycle is not a solve
    newton.configure_preconditioner = [&mg](KSP ksp, Mat jacobian) {
      WARPFEM_PETSC_CHECK(KSPSetTolerances(ksp, 1e-10, 1e-50, PETSC_DEFAULT, 1000));
      mg->configure(ksp, {jacobian});
    };
    log::info("linear solves: ", newton.ksp_type, " with geometric multigrid (", mg->num_levels(),
              " levels, Galerkin coarse operators, ", format_seconds(watch.seconds()), ")");
  }
  auto write = [&](int index, double time, Vec state) {
    if (!output) return;
    result.vtk_files.push_back(output->write(index, time, state));
  };

  // 4. Solve: quasi-static load stepping or transient generalized-α.
  Stopwatch solve_watch;
  if (cfg.problem.analysis == "quasi_static") {
    log::info("quasi-static: load factor 0 → 1 in ", cfg.load_stepping.steps, " step(s)");
    fem::QuasiStaticSolver solver(op, newton, {cfg.load_stepping.steps, cfg.load_stepping.min_increment});
    int index = 0;
    double last_load = 0;
    write(0, 0.0, u.get());
    try {
      const auto report = solver.solve(u.get(), [&](const fem::LoadStep& step, Vec state) {
        ++index;
        last_load = step.load;
        if (index % cfg.output.every == 0 || step.load >= 1.0) write(index, step.load, state);
      });
      result.load_steps = report.steps;
      result.rejected_steps = report.rejected_steps;
      result.newton_iterations = report.newton_iterations();
      result.domain_rejections = report.domain_rejections;
    } catch (const Error& e) {
      if (output && output->last_index() != index) write(index, last_load, u.get());
      throw at_config_key(e, cfg.file, "/load_stepping");
    }
  } else {
    petsc::Vector v = op.space().create_vector();
    interpolate_initial_velocity(cfg, op, v.get());
    fem::TransientOptions t;
    t.time_step = cfg.time.step;
    t.end_time = cfg.time.end;
    t.rho_infinity = cfg.time.rho_infinity;
    t.damping = cfg.time.damping;
    t.compute_energy = options.compute_energy;
    log::info("transient: generalized-α (ρ∞ = ", t.rho_infinity, "), Δt = ", t.time_step, ", end ",
              t.end_time);
    fem::TransientSolver solver(op, t, newton);
    int last_step = -1;
    double last_time = 0;
    try {
      const auto report = solver.solve(u.get(), v.get(), [&](const fem::TransientStep& s, Vec state, Vec) {
        result.history.push_back(s);
        last_step = s.step;
        last_time = s.time;
        if (s.step % cfg.output.every == 0 || s.time >= cfg.time.end * (1 - 1e-12))
          write(s.step, s.time, state);
      });
      result.time_steps = report.steps;
      result.newton_iterations = report.newton_iterations;
      result.domain_rejections = report.domain_rejections;
    } catch (const Error& e) {
      if (output && last_step >= 0 && output->last_index() != last_step) write(last_step, last_time, u.get());
      throw at_config_key(e, cfg.file, "/time");
    }
  }
  result.solve_seconds = solve_watch.seconds();

  // 5. Report.
  result.max_displacement = max_nodal_displacement(op.space(), u.get());
  result.min_det_F = op.min_det_F(u.get());
  log::info("solved: ", result.newton_iterations, " Newton iterations in ",
            format_seconds(result.solve_seconds), "; max |u| = ", std::scientific, std::setprecision(4),
            result.max_displacement, ", min det F = ", std::fixed, result.min_det_F);
  if (options.gather_solution) result.displacement = op.space().gather_all(u.get());
  if (output) {
    result.pvd_file = output->pvd_path();
    log::info("wrote ", result.vtk_files.size(), " VTK file(s) and ", result.pvd_file);
  }
  log::info("total ", format_seconds(total.seconds()));
  return result;
}

int run_elasticity_command(const std::string& config_path, const std::string& output_dir) {
  io::ElasticityConfig cfg = io::load_elasticity_config(config_path);
  if (!output_dir.empty()) cfg.output.directory = output_dir;
  log::set_level(log::parse_level(cfg.verbosity));
  Environment::insert_petsc_options(cfg.solver.petsc_options, config_path + ": /solver/petsc_options");
  log::info("warpfem run ", config_path, " on ", Environment::size(), " rank(s)");
  log::info("output directory ", cfg.output.directory,
            output_dir.empty() ? " (a relative output.directory starts at the config's directory)" : "");
  try {
    run_elasticity(cfg, PETSC_COMM_WORLD);
  } catch (const Error& e) {
    throw io::in_config(e, config_path);  // errors that name a config field come from this config
  }
  return 0;
}

}  // namespace warpfem::apps
