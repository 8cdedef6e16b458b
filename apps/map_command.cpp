// warpfem map: build a map from a config, explain why it is bijective, write
// the warped source grid, and optionally map the user's own points.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "apps/command_line.hpp"
#include "apps/commands.hpp"
#include "apps/points_csv.hpp"
#include "apps/polyhedron_map.hpp"
#include "core/collective_error.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/timer.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/postprocessing/output_mesh.hpp"
#include "io/atomic_file.hpp"
#include "io/polyhedron_config.hpp"
#include "io/run_config.hpp"
#include "io/vtk_writer.hpp"
#include "mapping/adaptive_partition.hpp"
#include "mapping/composite_mean_value_map.hpp"
#include "mapping/distortion.hpp"
#include "mapping/make_map.hpp"
#include "mapping/polygon_sampling.hpp"
#include "mapping/source_points.hpp"

namespace warpfem::apps {
namespace {

const char* kMapUsage =
    "usage: warpfem map --config map.json [--certify] [--points in.csv --out out.csv] [--output-dir DIR]";

std::string fmt(double v, int precision = 4) {
  std::ostringstream os;
  os << std::setprecision(precision) << v;
  return os.str();
}

void report_map(const mapping::Map<2>& map, const mapping::MapSpec& spec, const mapping::MapCheck& check) {
  const Polygon& source = *spec.source;
  if (check.samples > 0) log::info("check passed: ", check.summary());
  if (!check.certificate && !spec.certify && spec.type != "identity")
    log::info(mapping::is_certifiable(map) ? "certificate: not requested (--certify or \"certify\": true)"
                                           : "certificate: not certified (sampled check only)");
  if (const auto* composite = dynamic_cast<const mapping::CompositeMeanValueMap*>(&map)) {
    const mapping::CompositeReport r = mapping::analyze_composite(*composite, spec.sample_resolution);
    std::ostringstream times;
    for (std::size_t k = 0; k < r.times.size(); ++k) times << (k ? ", " : "") << fmt(r.times[k], 6);
    log::info("partition (", r.steps(), " steps): ", times.str());
    for (Index k = 0; k < r.steps(); ++k)
      log::info("  step ", k, " [", fmt(r.times[k], 6), ", ", fmt(r.times[k + 1], 6),
                "]: min det J_k along the sample ", fmt(r.step_min_det_along[static_cast<std::size_t>(k)]));
    log::info("composite: min det J_f = ", fmt(r.composite_min_det), " on ", r.samples,
              " samples (grid + points clustered at every vertex and edge)");
    log::info("distortion: conformal mean ", fmt(r.distortion.conformal.mean), " max ",
              fmt(r.distortion.conformal.max), "; isometric mean ", fmt(r.distortion.isometric.mean), " max ",
              fmt(r.distortion.isometric.max));
    const Points<2> sample = mapping::bijectivity_sample(source, spec.sample_resolution);
    const mapping::CompositeMeanValueMap g = composite->backward();
    log::info("backward map g (thesis §4.3): max |x - g(f(x))| = ",
              fmt(mapping::round_trip_error(map, g, sample)), " over ", sample.rows(), " samples");
    return;
  }
  const Points<2> sample = mapping::bijectivity_sample(source, spec.sample_resolution);
  Points<2> x;
  Jacobians<2> J;
  map.eval_with_jacobian(sample, x, J);
  const auto s = mapping::summarize_distortion<2>(J);
  log::info("min det J_f = ", fmt(s.min_det), " on ", s.samples, " samples; distortion: conformal mean ",
            fmt(s.conformal.mean), " max ", fmt(s.conformal.max), "; isometric mean ", fmt(s.isometric.mean),
            " max ", fmt(s.isometric.max));
}

/// f, J_f and the inverse residual at the user's points; throws listing up to
/// ten points where f cannot be evaluated or folds (never writes such values).
void map_user_points(const mapping::Map<2>& map, const Points<2>& x0, const std::string& file, Points<2>& x,
                     VectorX& det) {
  Jacobians<2> J;
  VectorX residual;
  map.eval_with_residual(x0, x, J, residual);
  det = mapping::jacobian_determinants<2>(J);
  const Real tolerance = map.inverse_tolerance();
  std::ostringstream bad;
  Index count = 0;
  for (Index p = 0; p < x0.rows(); ++p) {
    std::string why;
    if (!(residual(p) <= tolerance))
      why =
          "the inverse does not converge (residual " + fmt(residual(p), 3) + " > " + fmt(tolerance, 3) + ")";
    else if (!x.row(p).allFinite() || !std::isfinite(det(p)))
      why = "f or J_f is not finite";
    else if (det(p) <= 0)
      why = "det J_f = " + fmt(det(p), 3) + " <= 0";
    if (why.empty()) continue;
    if (count++ < 10)
      bad << (count > 1 ? "; " : "") << "point " << p + 1 << " (" << fmt(x0(p, 0), 10) << ", "
          << fmt(x0(p, 1), 10) << "): " << why;
  }
  if (count == 0) return;
  if (count > 10) bad << " (" << count << " of " << x0.rows() << " points; the first ten are listed)";
  throw Error("the map cannot be evaluated at these points: " + bad.str(),
              {.file = file, .key_path = "", .hint = "no output written; see the map check in the log"});
}

}  // namespace

int map_command(const std::vector<std::string>& args) {
  std::string config_path, points_in, points_out, output_dir;
  bool certify = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    auto value = [&](const char* flag) -> std::string {
      if (i + 1 >= args.size())
        throw Error(std::string(flag) + " needs a value", {.file = "", .key_path = "", .hint = kMapUsage});
      return args[++i];
    };
    if (args[i] == "--config")
      config_path = value("--config");
    else if (args[i] == "--points")
      points_in = value("--points");
    else if (args[i] == "--out")
      points_out = value("--out");
    else if (args[i] == "--output-dir")
      output_dir = value("--output-dir");
    else if (args[i] == "--certify")
      certify = true;
    else if (config_path.empty() && args[i].rfind("-", 0) != 0)
      config_path = args[i];
    else
      check_flag(args[i], {"--config", "--certify", "--points", "--out", "--output-dir"}, kMapUsage);
  }
  if (config_path.empty()) throw Error("missing --config", {.file = "", .key_path = "", .hint = kMapUsage});
  if (points_in.empty() != points_out.empty())
    throw Error("--points and --out go together", {.file = "", .key_path = "", .hint = kMapUsage});

  const nlohmann::json json = io::ConfigNode::parse_file(config_path);
  if (io::is_polyhedron_map(json))
    return polyhedron_map_command(json, config_path, points_in, points_out, output_dir);
  const io::ConfigNode root(json, config_path);
  log::set_level(log::parse_level(io::parse_verbosity(root)));
  mapping::MapSpec spec = io::parse_required_map(root);
  spec.certify = spec.certify || certify;
  const io::ConfigNode out = root.child("output");
  std::string directory = io::config_relative_path(config_path, out.get_string("directory", "output/map"));
  const std::string name = out.get_string("name", "map");
  const double edge = out.get_double("grid_edge_length", 0.0, 0.0);
  const bool write_vtk = out.get_bool("vtk", true);
  out.finish();
  const io::SizeLimits limits = io::parse_limits(root);
  root.finish();
  io::check_map_size(root, spec, limits);
  if (edge > 0 && write_vtk)
    io::check_grid_size(root, *spec.source, edge, limits, "/output/grid_edge_length");
  if (!output_dir.empty()) directory = output_dir;

  Stopwatch watch;
  mapping::MapCheck check;
  // errors, including a refused (folding) map, name spec.origin = the config file
  const mapping::MapPtr<2> map = mapping::make_map(spec, &check);
  log::info("map: ", map->describe(), " (built and checked in ", format_seconds(watch.seconds()), ")");
  report_map(*map, spec, check);

  if (!points_in.empty()) {
    Points<2> x0 = read_points_csv<2>(points_in);
    const mapping::SourcePointsReport accepted = mapping::accept_source_points(*spec.source, x0, points_in);
    if (accepted.snapped > 0)
      log::info(
          accepted.snapped,
          " points within 1e-12 of the diameter outside the source polygon were moved onto its boundary");
    Points<2> x;
    VectorX det;
    map_user_points(*map, x0, points_in, x, det);
    std::ostringstream csv;
    csv << "x,y,fx,fy,det_J\n" << std::setprecision(17);
    for (Index p = 0; p < x0.rows(); ++p)
      csv << x0(p, 0) << ',' << x0(p, 1) << ',' << x(p, 0) << ',' << x(p, 1) << ',' << det(p) << '\n';
    warpfem::run_collectively(MPI_COMM_WORLD, [&] {
      if (Environment::rank() == 0) io::write_text_atomically(points_out, csv.str());
    });
    log::info("mapped ", x0.rows(), " points: ", points_out);
  }

  if (write_vtk) {
    const Polygon& source = *spec.source;
    const double h = edge > 0 ? edge : (source.bbox_max() - source.bbox_min()).norm() / 40.0;
    const warpfem::Mesh<2> mesh = warpfem::mesh_polygon(source, {.max_edge_length = h});
    const fem::DofMap<2> dofs(mesh, fem::LagrangeElement<2>(mesh.cell_type, 1));
    const fem::DofDistribution<2> dist(MPI_COMM_WORLD, mesh, dofs);
    const fem::OutputMesh<2> grid = fem::make_output_mesh(mesh, dist, *map, 2);
    fem::log_untangling(MPI_COMM_WORLD, grid);
    Points<2> x;
    Jacobians<2> J;
    map->eval_with_jacobian(grid.reference_points, x, J);
    VectorX conformal, isometric;
    mapping::distortion<2>(J, conformal, isometric);
    io::VtkOutput<2> vtk;
    vtk.mesh = &grid;
    auto field = [](const char* n, const VectorX& v) {
      return io::VtkField{n, 1, std::vector<double>(v.data(), v.data() + v.size())};
    };
    vtk.point_fields = {field("det_Jf", grid.map_det), field("conformal_distortion", conformal),
                        field("isometric_distortion", isometric)};
    std::vector<double> x0(static_cast<std::size_t>(3 * grid.reference_points.rows()), 0.0);
    for (Index p = 0; p < grid.reference_points.rows(); ++p)
      x0[3 * p] = grid.reference_points(p, 0), x0[3 * p + 1] = grid.reference_points(p, 1);
    vtk.point_fields.push_back({"x0", 3, std::move(x0)});
    const std::string file = io::write_vtk(MPI_COMM_WORLD, vtk, directory, name);
    log::info("wrote ", file, " (warped source grid: ", mesh.num_cells(), " curved triangles)");
  }
  return 0;
}

}  // namespace warpfem::apps
