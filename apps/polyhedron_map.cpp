#include "apps/polyhedron_map.hpp"

#include <mpi.h>

#include <iomanip>
#include <map>
#include <sstream>

#include "apps/map_slice_picture.hpp"
#include "apps/points_csv.hpp"
#include "core/collective_error.hpp"
#include "core/environment.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/tetgen_mesher.hpp"
#include "core/timer.hpp"
#include "io/atomic_file.hpp"
#include "io/png_image.hpp"
#include "io/polyhedron_config.hpp"
#include "io/run_config.hpp"
#include "io/size_limits.hpp"
#include "io/vtk_writer.hpp"
#include "mapping/distortion.hpp"
#include "mapping/make_map.hpp"
#include "mapping/polyhedron_composite_map.hpp"
#include "mapping/source_points.hpp"

namespace warpfem::apps {
namespace {

/// Memory per tetrahedron of the grid while it is built, mapped and written
/// (TetGen's own structures dominate).
constexpr double kBytesPerGridCell = 1000;

std::string fmt(double v, int precision = 4) {
  std::ostringstream os;
  os << std::setprecision(precision) << v;
  return os.str();
}

void report_map(const mapping::Map<3>& map, const mapping::PolyhedronMapSpec& spec,
                const mapping::PolyhedronMapCheck& check) {
  if (check.samples > 0) log::info("check passed: ", check.summary());
  const auto* composite = dynamic_cast<const mapping::PolyhedronCompositeMap*>(&map);
  if (!composite) return;
  std::ostringstream times;
  for (std::size_t k = 0; k < composite->times().size(); ++k)
    times << (k ? ", " : "") << fmt(composite->times()[k], 6);
  log::info("partition (", composite->steps(), " steps): ", times.str());
  const Points<3> sample = mapping::polyhedron_check_sample(*spec.source, spec.sample_per_feature);
  Points<3> x;
  Jacobians<3> J;
  map.eval_with_jacobian(sample, x, J);
  const auto s = mapping::summarize_distortion<3>(J);
  log::info("distortion on the check sample: conformal mean ", fmt(s.conformal.mean), " max ",
            fmt(s.conformal.max), "; isometric mean ", fmt(s.isometric.mean), " max ", fmt(s.isometric.max));
}

/// f and det J_f at the user's points; throws listing up to ten points where
/// f folds or is not finite (never writes such values).
void map_points(const mapping::Map<3>& map, const Points<3>& x0, const std::string& file, Points<3>& x,
                VectorX& det) {
  Jacobians<3> J;
  map.eval_with_jacobian(x0, x, J);
  det = mapping::jacobian_determinants<3>(J);
  std::ostringstream bad;
  Index count = 0;
  for (Index p = 0; p < x0.rows(); ++p) {
    if (x.row(p).allFinite() && det(p) > 0 && std::isfinite(det(p))) continue;
    if (count++ < 10)
      bad << (count > 1 ? "; " : "") << "point " << p + 1 << " (" << fmt(x0(p, 0), 10) << ", "
          << fmt(x0(p, 1), 10) << ", " << fmt(x0(p, 2), 10) << "): det J_f = " << fmt(det(p), 3);
  }
  if (count == 0) return;
  if (count > 10) bad << " (" << count << " of " << x0.rows() << " points; the first ten are listed)";
  throw Error("the map folds or is not finite at these points: " + bad.str(),
              {.file = file, .key_path = "", .hint = "no output written; see the map check in the log"});
}

/// This rank's share of the cells (a contiguous range) with its own vertices.
io::VtkCells local_cells(const Mesh<3>& mesh, Points<3>& reference) {
  const int rank = Environment::rank(), size = Environment::size();
  const Index first = mesh.num_cells() * rank / size, last = mesh.num_cells() * (rank + 1) / size;
  std::map<Index, Index> local;
  io::VtkCells out;
  out.cells.resize(last - first, 4);
  for (Index c = first; c < last; ++c)
    for (int k = 0; k < 4; ++k)
      out.cells(c - first, k) = static_cast<TableIndex>(
          local.try_emplace(mesh.cells(c, k), static_cast<Index>(local.size())).first->second);
  reference.resize(static_cast<Index>(local.size()), 3);
  for (const auto& [global, l] : local) reference.row(l) = mesh.vertices.row(global);
  return out;
}

}  // namespace

int polyhedron_map_command(const nlohmann::json& json, const std::string& config_path,
                           const std::string& points_in, const std::string& points_out,
                           const std::string& output_dir) {
  const io::ConfigNode root(json, config_path);
  log::set_level(log::parse_level(io::parse_verbosity(root)));
  const mapping::PolyhedronMapSpec spec = io::parse_polyhedron_map_spec(root.child("map"));
  const Polyhedron& source = *spec.source;
  const io::ConfigNode out = root.child("output");
  std::string directory = out.get_string("directory", "output/map");
  const std::string name = out.get_string("name", "map");
  const double volume = source.signed_volume();
  const double max_volume = out.get_double("grid_max_volume", volume / 4000, 0.0);
  const double quality = out.get_double("grid_quality_ratio", 2.0, 1.2);
  const bool write_vtk = out.get_bool("vtk", true);
  const std::vector<double> slices = out.get_doubles("slices");
  const int slice_pixels = static_cast<int>(out.get_int("slice_pixels", 240, 16, 4096));
  out.finish();
  for (std::size_t k = 0; k < slices.size(); ++k)
    if (!(slices[k] > source.bbox_min().z() && slices[k] < source.bbox_max().z()))
      throw out.error(
          "slices/" + std::to_string(k), "the plane z = " + fmt(slices[k]) + " misses the source polyhedron",
          "give heights between " + fmt(source.bbox_min().z()) + " and " + fmt(source.bbox_max().z()));
  const io::SizeLimits limits = io::parse_limits(root);
  root.finish();
  if (write_vtk && max_volume > 0 && volume / max_volume * kBytesPerGridCell > limits.memory_bytes &&
      limits.memory_bytes > 0)
    throw root.error("output/grid_max_volume",
                     "the warped grid would have at least " + io::estimate_text(volume / max_volume) +
                         " tetrahedra, more than fit in memory",
                     "use a larger grid_max_volume");
  if (!output_dir.empty()) directory = output_dir;

  Stopwatch watch;
  mapping::PolyhedronMapCheck check;
  const mapping::MapPtr<3> map = mapping::make_map(spec, &check);
  log::info("map: ", map->describe(), " (built and checked in ", format_seconds(watch.seconds()), ")");
  report_map(*map, spec, check);

  std::string points_csv;
  Index points_count = 0;
  if (!points_in.empty()) {
    Points<3> x0 = read_points_csv<3>(points_in);
    const mapping::SourcePointsReport accepted = mapping::accept_source_points(source, x0, points_in);
    if (accepted.snapped > 0)
      log::info(
          accepted.snapped,
          " points within 1e-12 of the diameter outside the source polyhedron were moved onto its surface");
    Points<3> x;
    VectorX det;
    map_points(*map, x0, points_in, x, det);
    std::ostringstream csv;
    csv << "x,y,z,fx,fy,fz,det_J\n" << std::setprecision(17);
    for (Index p = 0; p < x0.rows(); ++p)
      csv << x0(p, 0) << ',' << x0(p, 1) << ',' << x0(p, 2) << ',' << x(p, 0) << ',' << x(p, 1) << ','
          << x(p, 2) << ',' << det(p) << '\n';
    points_csv = csv.str();
    points_count = x0.rows();
  }

  // The grid is mapped and checked before anything is written.
  io::VtkCells cells;
  io::VtkOutput<3> vtk;
  Index grid_cells = 0;
  Real global_min = 1;
  if (write_vtk) {
    TetrahedralMeshOptions o;
    o.quality_ratio = quality;
    o.max_volume = max_volume;
    o.keep_surface = false;  // a surface that may be split lets the grid be fine up to the boundary
    const Mesh<3> mesh = [&] {
      try {
        return mesh_polyhedron(source, o);
      } catch (const Error& e) {
        throw Error(e.message(), {.file = config_path, .key_path = "/output", .hint = e.context().hint});
      }
    }();
    Points<3> x0;
    grid_cells = mesh.num_cells();
    cells = local_cells(mesh, x0);
    Jacobians<3> J;
    map->eval_with_jacobian(x0, cells.points, J);
    const VectorX det = mapping::jacobian_determinants<3>(J);
    VectorX conformal, isometric;
    mapping::distortion<3>(J, conformal, isometric);
    const Real min_det = x0.rows() ? mapping::min_entry(det.data(), det.size()) : 1.0;
    MPI_Allreduce(&min_det, &global_min, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    if (!(global_min > 0))
      throw Error("the map is not bijective: det J_f = " + fmt(global_min) +
                      " <= 0 at a vertex of the warped grid (between the check samples)",
                  {.file = config_path,
                   .key_path = "/map",
                   .hint = "use a finer partition (more steps or max_halvings) or deform the target less; "
                           "nothing was written"});
    vtk.cells = &cells;
    auto field = [](const char* n, const VectorX& v) {
      return io::VtkField{n, 1, std::vector<double>(v.data(), v.data() + v.size())};
    };
    vtk.point_fields = {field("det_Jf", det), field("conformal_distortion", conformal),
                        field("isometric_distortion", isometric)};
    vtk.point_fields.push_back({"x0", 3, std::vector<double>(static_cast<std::size_t>(3 * x0.rows()))});
    for (Index p = 0; p < x0.rows(); ++p)
      for (int d = 0; d < 3; ++d)
        vtk.point_fields.back().values[static_cast<std::size_t>(3 * p + d)] = x0(p, d);
  }

  io::Image picture;
  if (!slices.empty() && spec.target)
    picture = map_slice_picture(*map, source, *spec.target, slices, slice_pixels);

  if (!points_in.empty()) {
    warpfem::run_collectively(MPI_COMM_WORLD, [&] {
      if (Environment::rank() == 0) io::write_text_atomically(points_out, points_csv);
    });
    log::info("mapped ", points_count, " points: ", points_out);
  }
  if (write_vtk) {
    const std::string file = io::write_vtk(MPI_COMM_WORLD, vtk, directory, name);
    log::info("wrote ", file, " (warped source grid: ", grid_cells,
              " tetrahedra, min det J_f = ", fmt(global_min), ")");
  }
  if (picture.width > 0) {
    const std::string file = directory + "/" + name + "_slices.png";
    warpfem::run_collectively(MPI_COMM_WORLD, [&] {
      if (Environment::rank() == 0) {
        io::prepare_output_directory(directory);
        io::write_png(file, picture);
      }
    });
    log::info(
        "wrote ", file, " (slices z = ",
        [&] {
          std::string list;
          for (double z : slices) list += (list.empty() ? "" : ", ") + fmt(z);
          return list;
        }(),
        " seen from above, coloured by det J_f)");
  }
  return 0;
}

}  // namespace warpfem::apps
