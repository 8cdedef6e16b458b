#include "apps/poisson_run.hpp"

#include <petscvec.h>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/timer.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/physics/poisson.hpp"
#include "fem/postprocessing/output_mesh.hpp"
#include "io/expression.hpp"
#include "io/vtk_writer.hpp"
#include "mapping/make_map.hpp"
#include "multigrid/poisson_multigrid.hpp"

namespace warpfem::apps {

PoissonRunResult run_poisson(const io::RunConfig& cfg, MPI_Comm comm, const PoissonRunOptions& options) {
  PoissonRunResult result;
  Stopwatch total;
  int size = 1;
  MPI_Comm_size(comm, &size);

  Stopwatch watch;
  const mapping::MapPtr<2> map = mapping::make_map(cfg.map);
  log::info("map: ", map->describe(), " (", format_seconds(watch.seconds()), ")");

  const Polygon& source = *cfg.map.source;
  const Polygon& target = cfg.map.target ? *cfg.map.target : source;
  fem::PoissonData<2> data;
  data.source = io::Expression(cfg.poisson.source, cfg.file, "/problem/source").as_function_2d();
  data.dirichlet = io::make_boundary_conditions(cfg.poisson.dirichlet, cfg.file);
  data.neumann = io::make_boundary_conditions(cfg.poisson.neumann, cfg.file);
  data.boundary_polygon = source;
  const int qdeg = cfg.poisson.quadrature_degree > 0 ? cfg.poisson.quadrature_degree
                                                     : warpfem::default_quadrature_degree(cfg.poisson.order);
  const fem::GeometryStorage storage =
      cfg.poisson.geometry == "streamed" ? fem::GeometryStorage::streamed : fem::GeometryStorage::cached;
  // Geometric multigrid on the nested hierarchy (default) needs at least one refinement;
  // otherwise the single level is solved with the configured (or algebraic) preconditioner.
  const bool use_mg = cfg.solver.linear.pc_type == "mg" && cfg.mesh.refinements > 0;
  watch.reset();
  std::unique_ptr<multigrid::PoissonMultigridSolver<2>> mg;
  std::unique_ptr<warpfem::Mesh<2>> single_mesh;
  std::unique_ptr<fem::PoissonProblem<2>> single;
  if (use_mg) {
    multigrid::PoissonMultigridOptions mg_options;
    mg_options.linear = cfg.solver.linear;
    mg_options.multigrid = cfg.solver.multigrid;
    mg_options.finest_geometry = storage;
    mg = std::make_unique<multigrid::PoissonMultigridSolver<2>>(
        comm, fem::make_coarse_mesh(source, target, *map, cfg.mesh), cfg.mesh.refinements, map,
        cfg.poisson.order, qdeg, data, mg_options);
  } else {
    single_mesh = std::make_unique<warpfem::Mesh<2>>(fem::make_coarse_mesh(source, target, *map, cfg.mesh));
    for (int r = 0; r < cfg.mesh.refinements; ++r)
      *single_mesh = warpfem::refine_uniformly(*single_mesh).mesh;
    single = std::make_unique<fem::PoissonProblem<2>>(comm, *single_mesh, map, cfg.poisson.order, qdeg, data,
                                                      storage);
    single->assemble();
  }
  fem::PoissonProblem<2>& problem = use_mg ? mg->finest() : *single;
  const warpfem::Mesh<2>& mesh = problem.mesh();
  result.num_cells = mesh.num_cells();
  result.h = mesh.max_edge_length();
  if (mesh.partial)  // stored only around this rank's cells: the largest over the ranks
    MPI_Allreduce(MPI_IN_PLACE, &result.h, 1, MPI_DOUBLE, MPI_MAX, comm);
  result.num_dofs = problem.dofs().num_dofs();
  log::info("mesh of Ω0: ", mesh.num_cells(), " ", warpfem::to_string(mesh.cell_type), "s, ",
            mesh.num_vertices(), " vertices, h = ", std::setprecision(4), result.h, " (",
            cfg.mesh.refinements, " refinements)");
  log::info("assembled P", cfg.poisson.order, " Poisson", use_mg ? " on every level" : "", ": ",
            result.num_dofs, " DOFs on ", size, " rank(s), ",
            problem.geometry().num_cells() * problem.geometry().points_per_cell(),
            " warped quadrature points on rank 0 (", format_seconds(watch.seconds()), ")");

  // A NaN or inf load would only surface as a diverging multigrid smoother.
  PetscReal rhs_norm = 0;
  PetscCallAbort(comm, VecNorm(problem.rhs(), NORM_INFINITY, &rhs_norm));
  if (!std::isfinite(rhs_norm))
    throw Error(
        "the assembled load vector contains NaN or inf: the source term (or a boundary value) is not "
        "finite somewhere in the domain",
        {.file = cfg.file,
         .key_path = "/problem/source",
         .hint = "check /problem/source, /problem/dirichlet and /problem/neumann for division by zero "
                 "or sqrt/log of negative values on the target domain"});

  if (use_mg) {
    result.solve = mg->solve().linear;
  } else {
    petsc::LinearSolveOptions linear = cfg.solver.linear;
    if (linear.pc_type == "mg")
      linear.pc_type = "gamg";  // one level: nothing to build a geometric hierarchy from
    result.solve = problem.solve(linear);
  }
  log::info("solved with ", result.solve.ksp_type, "/", result.solve.pc_type,
            use_mg ? " (" + std::to_string(cfg.mesh.refinements + 1) + " levels)" : std::string(), ": ",
            result.solve.iterations, " iterations, residual ", std::scientific, std::setprecision(2),
            result.solve.residual_norm, " (setup ", format_seconds(result.solve.setup_seconds), ", solve ",
            format_seconds(result.solve.solve_seconds), ")");

  result.area = problem.area();
  if (!cfg.poisson.exact_solution.empty()) {
    const io::Expression exact(cfg.poisson.exact_solution, cfg.file, "/problem/exact_solution");
    const auto u = exact.as_function_2d();
    const fem::GradientFunction<2> grad = [&exact](const Point<2>& x, double t) {
      return exact.gradient<2>(x, t);
    };
    const auto e = problem.errors(u, grad);
    result.l2_error = e.l2;
    result.h1_error = e.h1_semi;
    log::info("error against exact solution: L2 ", std::scientific, std::setprecision(4), e.l2,
              ", H1-seminorm ", e.h1_semi);
  }
  if (options.gather_solution) result.solution = problem.distribution().gather_all(problem.solution());

  if (options.write_output && cfg.output.vtk) {
    watch.reset();
    const int order = cfg.output.vtk_order > 0 ? cfg.output.vtk_order
                                               : std::max(cfg.poisson.order, map->is_affine() ? 1 : 2);
    const fem::OutputMesh<2> out = fem::make_output_mesh(mesh, problem.distribution(), *map, order);
    fem::log_untangling(comm, out);
    result.output_subdivided_cells = out.num_subdivided_cells;
    result.output_folded_cells = out.num_tangled_cells;
    const VectorX u = out.interpolate(problem.dofs(), problem.distribution(),
                                      problem.distribution().gather_relevant(problem.solution()));
    const double nodes_seconds = watch.seconds();
    io::VtkOutput<2> vtk;
    vtk.mesh = &out;
    vtk.compression = io::vtk_compression(cfg.output.compression);
    vtk.point_fields.push_back({"u", 1, std::vector<double>(u.data(), u.data() + u.size())});
    vtk.point_fields.push_back(
        {"det_Jf", 1, std::vector<double>(out.map_det.data(), out.map_det.data() + out.map_det.size())});
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    vtk.cell_fields.push_back(
        {"rank", 1, std::vector<double>(static_cast<std::size_t>(out.cells.rows()), rank)});
    result.output_file = io::write_vtk(comm, vtk, cfg.output.directory, cfg.output.name);
    log::info("wrote ", result.output_file, " (", format_seconds(watch.seconds()), ": ", out.points.rows(),
              " nodes placed by the map and values interpolated in ", format_seconds(nodes_seconds), ")");
  }
  log::info("total ", format_seconds(total.seconds()));
  return result;
}

}  // namespace warpfem::apps
