#include "apps/convergence_study.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

#include "apps/external_program.hpp"
#include "apps/study_target_mesh.hpp"
#include "core/collective_error.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/petsc/linear_solve.hpp"
#include "core/timer.hpp"
#include "fem/assembly/integrate.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/geometry/interpolated_map.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "fem/physics/poisson.hpp"
#include "fem/postprocessing/reference_error.hpp"
#include "io/atomic_file.hpp"
#include "io/expression.hpp"
#include "io/png_image.hpp"
#include "mapping/make_map.hpp"

namespace warpfem::apps {
namespace fs = std::filesystem;

StudySpec parse_study_spec(const io::ConfigNode& node) {
  StudySpec s;
  s.levels = static_cast<int>(node.get_int("levels", s.levels, 2, 12));
  if (node.has("discretizations")) {
    const nlohmann::json& list = node.raw("discretizations");
    if (!list.is_array() || list.empty())
      throw node.error("discretizations", "expected a non-empty array, got " + io::json_excerpt(list));
    s.discretizations.clear();
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_string() || (list[i] != "warped" && list[i] != "standard" &&
                                   list[i] != "standard_recovered" && list[i] != "target_mesh"))
        throw node.error("discretizations/" + std::to_string(i),
                         "unknown discretization " + io::json_excerpt(list[i]),
                         "use \"warped\", \"standard\", \"standard_recovered\" or \"target_mesh\"");
      s.discretizations.push_back(list[i].get<std::string>());
    }
  }
  s.reference_levels = static_cast<int>(node.get_int("reference_levels", s.reference_levels, 1, 4));
  s.condition_number = node.get_bool("condition_number", s.condition_number);
  s.condition_number_max_dofs = node.get_int("condition_number_max_dofs", s.condition_number_max_dofs, 0);
  s.plot = node.get_bool("plot", s.plot);
  node.finish();
  return s;
}

namespace {

// Values that do not exist (the L2/H1 error of a discretization without a
// common parametrization with the reference, rates from them, inverted
// levels) print as "n/a" in the log and the Markdown table, and as an empty
// field in the CSV.
std::string sci(double v, int precision = 3) {
  if (std::isnan(v)) return "n/a";
  std::ostringstream os;
  os << std::scientific << std::setprecision(precision) << v;
  return os.str();
}
std::string fixed(double v, int precision = 2) {
  if (std::isnan(v)) return "n/a";
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << v;
  return os.str();
}
std::string csv_number(double v) {
  if (std::isnan(v)) return "";
  std::ostringstream os;
  os << std::setprecision(10) << v;
  return os.str();
}
// A convergence rate: "-" on a discretization's first level, which has none.
std::string rate_text(const StudyRow& row, double rate) {
  return row.has_rates ? fixed(rate) : "-";
}
std::string csv_rate(const StudyRow& row, double rate) {
  return row.has_rates ? csv_number(rate) : "";
}
// A count of a level where the discretization does not exist (inverted).
std::string count_text(const StudyRow& row, Index count, const char* none) {
  return row.dofs > 0 ? std::to_string(count) : none;
}
std::string condition_text(double v) {
  return std::isnan(v) ? "-" : sci(v, 2);
}

template <int dim>
fem::PoissonData<dim> poisson_data(const io::PoissonRunConfig<dim>& cfg) {
  fem::PoissonData<dim> data;
  data.source = io::expression_function<dim>(cfg.poisson.source, cfg.file, "/problem/source");
  data.dirichlet = io::make_boundary_conditions<dim>(cfg.poisson.dirichlet, cfg.file);
  data.neumann = io::make_boundary_conditions<dim>(cfg.poisson.neumann, cfg.file);
  if constexpr (dim == 2) data.boundary_polygon = *cfg.map.source;
  return data;
}

template <int dim>
Index boundary_vertex_count(const warpfem::Mesh<dim>& mesh) {
  std::vector<char> on(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f)
    for (Index k = 0; k < mesh.boundary_facets.cols(); ++k)
      on[static_cast<std::size_t>(mesh.boundary_facets(f, k))] = 1;
  return std::count(on.begin(), on.end(), 1);
}

/// Area (2D) or volume (3D) of the exact domain.
template <int dim>
double exact_measure(const io::PoissonRunConfig<dim>& cfg) {
  const auto& domain = cfg.map.target ? *cfg.map.target : *cfg.map.source;
  if constexpr (dim == 2)
    return domain.signed_area();
  else
    return domain.signed_volume();
}

/// The gnuplot script of the error plot. Paths are not written into it: gnuplot receives
/// them as arguments (`gnuplot -c study_errors.gp <png> <csv>`), so no file name can be
/// misread as gnuplot syntax, and the script stays usable after the folder is moved.
std::string plot_script(const StudySpec& spec, bool exact) {
  std::ostringstream gp;
  gp << "# usage: gnuplot -c study_errors.gp [study_errors.png] [study.csv]\n"
     << "png = ARGC >= 1 ? ARG1 : 'study_errors.png'\ncsv = ARGC >= 2 ? ARG2 : 'study.csv'\n"
     // Enhanced text for the 10^{k} tick labels only; titles are taken literally.
     << "set terminal pngcairo size 900,650 font ',11' enhanced\nset output png\n"
     << "set logscale xy\nset format y '10^{%L}'\nset grid\nset key bottom left\n"
     << "set xlabel 'degrees of freedom'\nset ylabel 'error'\n"
     << "set title 'Convergence: warped (exact geometry) vs standard FEM'\n"
     << "set datafile separator ','\nplot ";
  bool first = true;
  int style = 1;
  for (const auto& d : spec.discretizations) {
    // Column 5: L2 error (against the exact solution, or the reference for "warped" and
    // "target_mesh", which share a domain with it);
    // column 9: r(u_h) = | ‖u_h‖/‖u_ref‖ − 1 |, defined for every discretization.
    for (const auto& [column, label] : {std::pair{5, "L2 error"}, std::pair{9, "r(u_h)"}}) {
      if (column == 5 && !exact && d != "warped" && d != "target_mesh") continue;
      gp << (first ? "" : ", \\\n     ") << "csv using (strcol(1) eq '" << d << "' ? $4 : 1/0):" << column
         << " with linespoints lw 2 pt " << style << " title '" << d << " " << label << "' noenhanced";
      first = false;
      ++style;
    }
  }
  gp << "\nset output\n";
  return gp.str();
}

/// Writes study_errors.gp and, if gnuplot is installed, study_errors.png (atomically, and
/// only if gnuplot succeeded and the PNG is complete). gnuplot is optional: without it the
/// script is still written for later use.
void write_plot(const StudySpec& spec, bool exact, const std::string& dir, std::string& plot_file) {
  const std::string script = (fs::path(dir) / "study_errors.gp").string();
  io::write_text_atomically(script, plot_script(spec, exact));
  const std::string png = (fs::path(dir) / "study_errors.png").string();
  const std::string csv = (fs::path(dir) / "study.csv").string();
  const std::string tmp = io::temporary_path(dir, "study_errors.png");
  try {
    const ProgramResult r = run_program({"gnuplot", "-c", script, tmp, csv});
    if (!r.started) {
      log::warning("gnuplot not found: wrote ", script, " but no PNG (install gnuplot-nox)");
      return;
    }
    if (!r.succeeded())
      throw Error(r.timed_out ? "gnuplot did not finish within its time limit"
                              : "gnuplot failed (exit code " + std::to_string(r.exit_code) + ")",
                  {.file = png,
                   .key_path = "",
                   .hint = "see gnuplot's message above, run gnuplot -c " + script +
                           " by hand, or set /study/plot to false"});
    io::check_png_complete(tmp, png);
    io::sync_file(tmp, png);
    io::rename_into_place(tmp, png);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  plot_file = png;
}

}  // namespace

template <int dim>
StudyResult run_study(const io::PoissonRunConfig<dim>& cfg, const StudySpec& spec, MPI_Comm comm,
                      bool write_files) {
  StudyResult result;
  const mapping::MapPtr<dim> f = mapping::make_map(cfg.map);
  log::info("map: ", f->describe());
  const bool exact = !cfg.poisson.exact_solution.empty();
  const auto& domain = cfg.map.target ? *cfg.map.target : *cfg.map.source;
  const double exact_area = exact_measure(cfg);
  const int order = cfg.poisson.order;
  // A study compares areas and norms across discretizations: it over-integrates.
  const int qdeg = cfg.poisson.quadrature_degree > 0 ? cfg.poisson.quadrature_degree
                                                     : warpfem::measurement_quadrature_degree(order);
  const fem::PoissonData<dim> data = poisson_data(cfg);
  petsc::LinearSolveOptions linear = cfg.solver.linear;
  if (linear.pc_type == "mg") linear.pc_type = "gamg";  // the study solves each level on its own
  const int first = cfg.mesh.refinements;
  const int finest = first + spec.levels - 1;
  const fem::MeshHierarchy<dim> hierarchy(fem::make_coarse_mesh(*cfg.map.source, domain, *f, cfg.mesh),
                                          finest + (exact ? 0 : spec.reference_levels));

  if constexpr (dim == 3) {
    // Standard geometries and reference solutions locate points of one level in another.
    bool locates = !exact;
    for (const std::string& d : spec.discretizations)
      locates = locates || d == "standard" || d == "standard_recovered";
    if (locates && hierarchy.levels[0].cell_type != CellType::tetrahedron)
      throw Error("a 3D study with standard discretizations or a reference solution needs tetrahedra",
                  {.file = cfg.file,
                   .key_path = "/mesh/cell_type",
                   .hint = "use \"cell_type\": \"tetrahedron\", or give /problem/exact_solution and study "
                           "only the \"warped\" discretization"});
  }

  std::optional<io::Expression> u_exact;
  if (exact) u_exact.emplace(cfg.poisson.exact_solution, cfg.file, "/problem/exact_solution");
  const fem::ScalarFunction<dim> u_fn = [&u_exact](const Point<dim>& x, double t) {
    return u_exact->template at<dim>(x, t);
  };
  const fem::GradientFunction<dim> grad_fn = [&u_exact](const Point<dim>& x, double t) {
    return u_exact->template gradient<dim>(x, t);
  };

  // Reference: ‖u‖ from the exact solution, or the warped solution on the reference level.
  std::unique_ptr<fem::PoissonProblem<dim>> reference;
  double reference_norm = 0;
  if (!exact) {
    Stopwatch w;
    reference = std::make_unique<fem::PoissonProblem<dim>>(comm, hierarchy.finest(), f, order, qdeg, data);
    reference->assemble();
    reference->solve(linear);
    reference_norm = reference->solution_l2_norm();
    log::info("reference solution: level ", hierarchy.num_levels() - 1, ", ", reference->dofs().num_dofs(),
              " DOFs (", format_seconds(w.seconds()), ")");
  } else {
    // ‖u‖ over the exact domain, integrated on the finest warped level (cells split round-robin over ranks).
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    std::vector<Index> cells;
    for (Index c = rank; c < hierarchy.finest().num_cells(); c += size) cells.push_back(c);
    const fem::WarpedGeometry<dim> g(hierarchy.finest(), cells,
                                     warpfem::cell_quadrature<dim>(hierarchy.finest().cell_type, qdeg), *f);
    const double local = fem::integrate(g, [&](const Point<dim>& x) { return std::pow(u_fn(x, 0.0), 2); });
    MPI_Allreduce(&local, &reference_norm, 1, MPI_DOUBLE, MPI_SUM, comm);
    reference_norm = std::sqrt(reference_norm);
  }

  for (const std::string& d : spec.discretizations) {
    bool told_no_pointwise_error = false;
    std::shared_ptr<const mapping::Map<dim>> coarse_interpolant;
    if (d == "standard")
      coarse_interpolant = std::make_shared<fem::InterpolatedMap<dim>>(hierarchy.levels[first], *f);
    for (int level = first; level <= finest; ++level) {
      Stopwatch w;
      mapping::MapPtr<dim> map = f;
      fem::PoissonData<dim> level_data = data;
      std::optional<warpfem::Mesh<dim>> target_mesh;
      if (d == "target_mesh") {
        // Standard FEM on straight cells of the exact domain, as many DOFs as the warped level.
        const warpfem::Mesh<dim>& warped = hierarchy.levels[level];
        const Index dofs =
            fem::DofMap<dim>(warped, fem::LagrangeElement<dim>(warped.cell_type, order)).num_dofs();
        target_mesh = mesh_target_with_dofs<dim>(*cfg.map.source, domain, order, dofs);
        map = std::make_shared<mapping::IdentityMap<dim>>();
        if constexpr (dim == 2) level_data.boundary_polygon = domain;  // the parts, at points of Ω1
        // Dirichlet data fix the boundary DOFs: how many of the DOFs are free differs between the two.
        log::info("target mesh for level ", level, ": ", target_mesh->num_cells(), " cells, ",
                  target_mesh->num_vertices(), " vertices (", boundary_vertex_count(*target_mesh),
                  " on the boundary); the warped level has ", warped.num_vertices(), " (",
                  boundary_vertex_count(warped), ")");
      }
      const warpfem::Mesh<dim>& mesh = target_mesh ? *target_mesh : hierarchy.levels[level];
      if (d == "standard") map = coarse_interpolant;
      if (d == "standard_recovered") map = std::make_shared<fem::InterpolatedMap<dim>>(mesh, *f);
      std::unique_ptr<fem::PoissonProblem<dim>> owned;
      try {
        owned = std::make_unique<fem::PoissonProblem<dim>>(comm, mesh, map, order, qdeg, level_data);
      } catch (const Error& e) {
        // Straight elements through mapped vertices can be inverted on coarse meshes of
        // strongly curved domains: the standard discretization does not exist on this level.
        log::warning(d, " level ", level, ": no valid discretization (", e.message(), ")");
        StudyRow row;
        row.discretization = d + " (inverted)";
        row.level = level;
        row.h = mesh.max_edge_length();
        row.l2 = row.h1 = row.norm_ratio_error = row.area = row.area_error = row.seconds = std::nan("");
        result.rows.push_back(row);
        continue;
      }
      fem::PoissonProblem<dim>& problem = *owned;
      problem.assemble();
      const auto solve = problem.solve(linear);
      StudyRow row;
      row.discretization = d;
      row.level = level;
      row.h = mesh.max_edge_length();
      row.dofs = problem.dofs().num_dofs();
      row.iterations = solve.iterations;
      if (exact) {
        const auto e = problem.errors(u_fn, grad_fn);
        row.l2 = e.l2, row.h1 = e.h1_semi;
      } else if (d == "warped") {
        const auto e = fem::error_against_reference(problem, *reference);
        row.l2 = e.l2, row.h1 = e.h1_semi;
      } else if (d == "target_mesh") {
        const auto e = fem::straight_mesh_error_against_reference(problem, *reference);
        row.l2 = e.l2, row.h1 = e.h1_semi;
      } else {
        // Standard elements cover another domain than the reference's: no
        // point-wise error exists, r(u_h) compares the two.
        row.l2 = row.h1 = std::nan("");
        if (!told_no_pointwise_error)
          log::info(d,
                    ": no L2/H1 error against the warped reference (its domain is not the reference's, "
                    "so the two have no common points to compare); r(u_h) = | ||u_h|| / ||u_ref|| - 1 | "
                    "compares them");
        told_no_pointwise_error = true;
      }
      row.norm_ratio_error = std::abs(problem.solution_l2_norm() / reference_norm - 1);
      row.area = problem.area();
      row.area_error = std::abs(row.area - exact_area) / exact_area;
      if (spec.condition_number && row.dofs <= spec.condition_number_max_dofs)
        row.condition_number = petsc::estimate_condition_number(problem.matrix());
      if (!result.rows.empty() && result.rows.back().discretization == d) {
        const StudyRow& prev = result.rows.back();
        // Unstructured target meshes: against DOFs^(-1/dim), since their largest edge says little
        // about the resolution; no rate where the DOFs barely grew (the coarsest mesh twice).
        const double hr = d == "target_mesh"
                              ? std::log(static_cast<double>(row.dofs) / static_cast<double>(prev.dofs)) / dim
                              : std::log(prev.h / row.h);
        if (d != "target_mesh" || hr > 0.05) {
          row.has_rates = true;
          row.l2_rate = std::log(prev.l2 / row.l2) / hr;
          row.h1_rate = std::log(prev.h1 / row.h1) / hr;
        }
      }
      row.seconds = w.seconds();
      log::info(std::setw(18), d, " level ", level, ": ", std::setw(8), row.dofs, " DOFs  L2 ", sci(row.l2),
                " (", rate_text(row, row.l2_rate), ")  H1 ", sci(row.h1), " (", rate_text(row, row.h1_rate),
                ")  r(u_h) ", sci(row.norm_ratio_error), (dim == 2 ? "  area err " : "  volume err "),
                sci(row.area_error), "  cond ", condition_text(row.condition_number), "  (",
                format_seconds(row.seconds), ")");
      result.rows.push_back(row);
    }
  }

  if (!write_files) return result;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // Rank 0 writes the files; a failure there ends the study on every rank.
  warpfem::run_collectively(comm, [&] {
    if (rank != 0) return;
    const std::string dir = cfg.output.directory;
    io::prepare_output_directory(dir);
    std::ostringstream csv;
    csv << "discretization,level,h,dofs,l2_error,l2_rate,h1_error,h1_rate,r_uh,area,area_error,condition_"
           "number,iterations,seconds\n";
    for (const auto& r : result.rows)
      csv << r.discretization << ',' << r.level << ',' << csv_number(r.h) << ',' << count_text(r, r.dofs, "")
          << ',' << csv_number(r.l2) << ',' << csv_rate(r, r.l2_rate) << ',' << csv_number(r.h1) << ','
          << csv_rate(r, r.h1_rate) << ',' << csv_number(r.norm_ratio_error) << ',' << csv_number(r.area)
          << ',' << csv_number(r.area_error) << ',' << csv_number(r.condition_number) << ','
          << count_text(r, r.iterations, "") << ',' << csv_number(r.seconds) << '\n';
    result.csv_file = (fs::path(dir) / "study.csv").string();
    io::write_text_atomically(result.csv_file, csv.str());

    std::ostringstream md;
    md << "# Convergence study: " << cfg.file << "\n\n"
       << "Map: " << f->describe() << ". Elements: "
       << (hierarchy.levels[0].cell_type == warpfem::CellType::triangle ||
                   hierarchy.levels[0].cell_type == warpfem::CellType::tetrahedron
               ? "P"
               : "Q")
       << order << ". Errors against "
       << (exact ? "the exact solution `" + cfg.poisson.exact_solution + "`"
                 : "the warped solution on level " + std::to_string(hierarchy.num_levels() - 1))
       << (dim == 2 ? ". Exact area of the domain: " : ". Exact volume of the domain: ") << exact_area
       << ".\n\n"
       << "| discretization | level | h | DOFs | L2 error | rate | H1 error | rate | r(u_h) | "
       << (dim == 2 ? "area" : "volume")
       << " error | "
          "cond(L) | CG its |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : result.rows)
      md << "| " << r.discretization << " | " << r.level << " | " << sci(r.h, 2) << " | "
         << count_text(r, r.dofs, "-") << " | " << sci(r.l2) << " | " << rate_text(r, r.l2_rate) << " | "
         << sci(r.h1) << " | " << rate_text(r, r.h1_rate) << " | " << sci(r.norm_ratio_error) << " | "
         << sci(r.area_error) << " | " << condition_text(r.condition_number) << " | "
         << count_text(r, r.iterations, "-") << " |\n";
    md << "\nWarped: elements of the simple mesh warped by f (exact geometry). Standard: straight elements "
          "through the mapped coarse vertices, kept under refinement (the domain stays the coarse "
       << (dim == 2 ? "polygonal" : "polyhedral")
       << " approximation). Standard recovered: straight elements through the mapped vertices of each "
          "level (boundary vertices moved onto the exact boundary).";
    if (std::find(spec.discretizations.begin(), spec.discretizations.end(), "target_mesh") !=
        spec.discretizations.end())
      md << " Target mesh: straight "
         << (dim == 2 ? "triangles of the target polygon (CGAL)"
                      : "tetrahedra of the target polyhedron (TetGen)")
         << " with about the DOFs of the warped level, the exact domain meshed directly (identity map; rates "
            "against DOFs^(-1/"
         << dim << "))"
         << (exact
                 ? "."
                 : "; its errors against the reference are integrated at the reference's quadrature points.");
    const bool some_not_available =
        std::any_of(result.rows.begin(), result.rows.end(), [](const StudyRow& r) {
          return std::isnan(r.l2) && r.discretization.find("(inverted)") == std::string::npos;
        });
    if (some_not_available)
      md << "\n\nn/a: the standard discretizations solve on another domain than the reference, so no "
            "point-wise (L2, H1) error against it exists; r(u_h) = | ‖u_h‖/‖u_ref‖ − 1 | compares them.";
    if (std::any_of(result.rows.begin(), result.rows.end(), [](const StudyRow& r) {
          return r.discretization.find("(inverted)") != std::string::npos;
        }))
      md << "\n\n(inverted): straight elements through the mapped vertices are inverted on that level, so "
            "the "
            "discretization does not exist there.";
    md << "\n";
    result.markdown_file = (fs::path(dir) / "study.md").string();
    if (spec.plot) write_plot(spec, exact, dir, result.plot_file);
    if (!result.plot_file.empty()) md << "\n![errors](study_errors.png)\n";
    io::write_text_atomically(result.markdown_file, md.str());
    log::info("wrote ", result.csv_file, ", ", result.markdown_file,
              result.plot_file.empty() ? "" : ", " + result.plot_file);
  });
  return result;
}

template StudyResult run_study(const io::PoissonRunConfig<2>&, const StudySpec&, MPI_Comm, bool);
template StudyResult run_study(const io::PoissonRunConfig<3>&, const StudySpec&, MPI_Comm, bool);

}  // namespace warpfem::apps
