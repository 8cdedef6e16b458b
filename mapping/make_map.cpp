#include "mapping/make_map.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "mapping/adaptive_interpolant.hpp"
#include "mapping/adaptive_partition.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/composite_mean_value_map.hpp"
#include "mapping/harmonic/make_harmonic_map.hpp"
#include "mapping/harmonic/polyhedron_harmonic_map.hpp"
#include "mapping/map_check.hpp"
#include "mapping/mean_value_certificate.hpp"
#include "mapping/polyhedron_composite_map.hpp"
#include "mapping/spec_context.hpp"

namespace warpfem::mapping {
namespace {

const Polygon& require_polygon(const MapSpec& spec, const std::optional<Polygon>& p, const char* key) {
  if (!p)
    throw Error(std::string("map type \"") + spec.type + "\" needs a " + (key + 5) + " polygon",
                {.file = spec.origin, .key_path = key, .hint = "give a list of [x, y] vertices"});
  return *p;
}

MapPtr<2> build_map(const MapSpec& spec) {
  if (spec.type == "composite_harmonic") return make_harmonic_map(spec);
  if (spec.type != "composite_mean_value" && spec.type != "barycentric")
    throw Error(
        "unknown map type \"" + spec.type + "\"",
        {.file = spec.origin,
         .key_path = "map.type",
         .hint = "use \"identity\", \"barycentric\", \"composite_mean_value\" or \"composite_harmonic\""});

  const Polygon& source = require_polygon(spec, spec.source, "map.source");
  const Polygon& target = require_polygon(spec, spec.target, "map.target");
  with_spec_context(spec, "map.source", [&] { source.validate(); });
  with_spec_context(spec, "map.target", [&] {
    target.validate();
    require_same_vertex_count(source, target);
  });
  const Coordinates coords =
      with_spec_context(spec, "map.coordinates", [&] { return parse_coordinates(spec.coordinates); });

  if (spec.type == "barycentric")
    return with_spec_context(spec, "map.coordinates",
                             [&] { return std::make_shared<const BarycentricMap>(source, target, coords); });

  const VertexPathType vp =
      with_spec_context(spec, "map.vertex_path", [&] { return parse_vertex_path(spec.vertex_path); });
  const VertexPath path(source, target, vp);
  if (spec.partition == "adaptive" || spec.partition == "greedy") {
    if (spec.sample_resolution < 2)
      throw Error("sample_resolution must be at least 2, got " + std::to_string(spec.sample_resolution),
                  {.file = spec.origin, .key_path = "map.sample_resolution", .hint = "64 is a good default"});
    if (!(spec.min_interval > 0 && spec.min_interval < 1))
      throw Error("min_interval must lie in (0, 1)",
                  {.file = spec.origin, .key_path = "map.min_interval", .hint = "1e-4 is a good default"});
    if (!(spec.greedy_min_det > 0 && spec.greedy_min_det < 1))
      throw Error("greedy_min_det must lie in (0, 1)",
                  {.file = spec.origin, .key_path = "map.greedy_min_det", .hint = "0.2 is a good default"});
    if (spec.max_steps < 1)
      throw Error("max_steps must be a positive integer, got " + std::to_string(spec.max_steps),
                  {.file = spec.origin, .key_path = "map.max_steps", .hint = "256 is a good default"});
    AdaptiveOptions o;
    o.max_steps = spec.max_steps;
    o.sample_resolution = spec.sample_resolution;
    o.min_interval = spec.min_interval;
    o.coordinates = coords;
    o.strategy = spec.partition == "greedy" ? PartitionStrategy::greedy : PartitionStrategy::binary;
    o.greedy_min_det = spec.greedy_min_det;
    return with_spec_context(spec, "map.partition", [&] { return build_adaptive_composite(path, o).map; });
  }
  if (spec.partition == "uniform") {
    if (spec.steps < 1)
      throw Error("steps must be a positive integer, got " + std::to_string(spec.steps),
                  {.file = spec.origin, .key_path = "map.steps", .hint = "e.g. 16"});
    return with_spec_context(spec, "map.partition", [&] {
      return std::make_shared<const CompositeMeanValueMap>(path, uniform_partition(spec.steps), coords);
    });
  }
  if (spec.partition == "explicit")
    return with_spec_context(spec, "map.times", [&] {
      return std::make_shared<const CompositeMeanValueMap>(path, spec.times, coords);
    });
  throw Error("unknown partition \"" + spec.partition + "\"",
              {.file = spec.origin,
               .key_path = "map.partition",
               .hint = "use \"adaptive\", \"greedy\", \"uniform\" or \"explicit\""});
}

std::string point_text(const Point<3>& p) {
  std::ostringstream os;
  os << std::setprecision(6) << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

void require_polyhedra(const PolyhedronMapSpec& spec) {
  if (!spec.source || !spec.target)
    throw Error(
        "map type \"" + spec.type + "\" needs a source and a target polyhedron",
        {.file = spec.origin,
         .key_path = spec.source ? "map.target" : "map.source",
         .hint =
             "give {\"vertices\": [[x, y, z], ...], \"triangles\": [[i, j, k], ...]} or {\"file\": ...}"});
}

std::shared_ptr<const PolyhedronCompositeMap> build_polyhedron_map(const PolyhedronMapSpec& spec) {
  require_polyhedra(spec);
  const Polyhedron& source = *spec.source;
  const Polyhedron& target = *spec.target;
  with_spec_context(spec, "map.target", [&] { require_same_triangulation(source, target); });
  const VertexPathType path =
      with_spec_context(spec, "map.vertex_path", [&] { return parse_vertex_path(spec.vertex_path); });
  // A degenerate intermediate cage is the path's fault: name the field and the other path.
  const auto degenerate_cage = [&](const Error& e) {
    const bool linear = path == VertexPathType::linear;
    return Error(
        "the " + to_string(path) + " vertex path passes through a degenerate cage: " + e.message(),
        {.file = spec.origin,
         .key_path = "map.vertex_path",
         .hint = linear ? "use \"vertex_path\": \"intrinsic\" (it follows rotations without "
                          "shrinking the cage), deform the target less, or map in several stages "
                          "through intermediate targets"
                        : "some triangles turn by nearly a half turn relative to the whole cage; try "
                          "\"vertex_path\": \"linear\", or map in several stages through "
                          "intermediate targets"});
  };
  const auto build = [&](const char* field, const auto& make) {
    return with_spec_context(spec, field, [&] {
      try {
        return make();
      } catch (const Error& e) {
        if (e.message().rfind("intermediate polyhedron", 0) != 0) throw;
        throw degenerate_cage(e);
      }
    });
  };
  if (spec.partition == "adaptive") {
    PolyhedronPartitionOptions o;
    o.epsilon = spec.min_det;
    o.max_halvings = spec.max_halvings;
    o.vertex_path = path;
    return build("map.partition", [&] {
      return std::make_shared<const PolyhedronCompositeMap>(build_polyhedron_composite(source, target, o));
    });
  }
  std::vector<Real> times = spec.times;
  if (spec.partition == "uniform") {
    times.clear();
    for (int k = 0; k <= spec.steps; ++k) times.push_back(k == spec.steps ? 1.0 : Real(k) / spec.steps);
  }
  return build(spec.partition == "uniform" ? "map.steps" : "map.times",
               [&] { return std::make_shared<const PolyhedronCompositeMap>(source, target, times, path); });
}

void certify_into(const Map<2>& map, const MapSpec& spec, MapCheck& c) {
  if (!is_certifiable(map)) {
    log::info("certificate: none for ", spec.type,
              spec.type == "composite_harmonic" ? "" : " with " + spec.coordinates + " coordinates",
              " maps: not certified (sampled check only)");
    return;
  }
  c.certificate = certify_map(map);
  log::info("certificate: ", c.certificate->summary(), "; the map took ", format_seconds(c.build_seconds),
            " to build and check");
}

std::shared_ptr<const PolyhedronHarmonicMap> build_polyhedron_harmonic_map(const PolyhedronMapSpec& spec) {
  require_polyhedra(spec);
  with_spec_context(spec, "map.target", [&] { require_same_triangulation(*spec.source, *spec.target); });
  PolyhedronHarmonicOptions o;
  o.max_volume = spec.fem_max_volume;
  o.quality_ratio = spec.fem_quality_ratio;
  o.min_det = spec.min_det;
  o.spherical = spec.harmonic_intermediate == "sphere";
  return with_spec_context(spec, "map.fem_max_volume",
                           [&] { return build_polyhedron_harmonic(*spec.source, *spec.target, o); });
}

}  // namespace

MapPtr<3> make_map(const PolyhedronMapSpec& spec, PolyhedronMapCheck* check) {
  if (spec.type == "identity") return std::make_shared<IdentityMap<3>>();
  if (spec.type != "composite_mean_value" && spec.type != "composite_harmonic")
    throw Error("unknown map type \"" + spec.type + "\" for polyhedra",
                {.file = spec.origin,
                 .key_path = "map.type",
                 .hint = "use \"identity\", \"composite_mean_value\" or \"composite_harmonic\""});
  const bool harmonic = spec.type == "composite_harmonic";
  MapPtr<3> map;
  PolyhedronMapCheck c;
  if (harmonic) {
    Stopwatch watch;
    const auto h = build_polyhedron_harmonic_map(spec);
    const double built = watch.seconds();
    map = h;
    c = check_polyhedron_map(
        *h, [&](const Points<3>& y, Points<3>& x, VectorX& residual) { h->inverse(y, x, residual); },
        *spec.source, *spec.target, spec.sample_per_feature);
    log::info("harmonic maps built in ", format_seconds(built), ", checked in ",
              format_seconds(watch.seconds() - built));
  } else {
    Stopwatch watch;
    const auto composite = build_polyhedron_map(spec);
    const double built = watch.seconds();
    map = composite;
    c = check_polyhedron_map(*composite, *spec.source, *spec.target, spec.sample_per_feature);
    log::info("composite mean value map (", to_string(composite->path().type()), " vertex path, ",
              composite->steps(), " steps) built in ", format_seconds(built), ", checked in ",
              format_seconds(watch.seconds() - built));
  }
  if (!c.passed()) {
    std::ostringstream why;
    why << std::setprecision(4) << "the map is not bijective on its check sample (" << c.samples
        << " points clustered at every vertex, edge and face): ";
    if (c.nonpositive > 0)
      why << c.nonpositive << " samples with det J_f <= 0 or not finite, min det J_f = " << c.min_det
          << " at " << point_text(c.min_det_at);
    else if (c.outside > 0)
      why << c.outside << " images outside the target polyhedron";
    else
      why << c.failed_inverse << " samples whose inverse misses them, by up to " << c.max_round_trip
          << " of the source's size, at " << point_text(c.worst_inverse_at);
    throw Error(
        why.str(),
        {.file = spec.origin,
         .key_path = "/map",
         .hint = harmonic ? "refine the harmonic maps' meshes (smaller fem_max_volume), or use "
                            "\"type\": \"composite_mean_value\""
                          : "use a finer partition (more steps, or \"partition\": \"adaptive\" with more "
                            "max_halvings), or deform the target less"});
  }
  if (check) *check = c;
  return map;
}

namespace {

/// Whether "evaluation": "auto" interpolates. Cost model in exact point·vertex
/// evaluations of a mean value step: the exact map costs steps × vertices per
/// point, the interpolant about 70 per point and its build about a million
/// exact points; it is taken when it saves more than half its build on the
/// estimated points, a lower bound (a Delaunay mesh has 2–4 times more). The
/// ranks share the build. Harmonic maps
/// (an inverse by Newton's method per point) are interpolated on any large run.
bool interpolation_pays(const Map<2>& map, const MapSpec& spec) {
  const double points = spec.evaluation_points;
  if (points < 1e6) return false;
  if (spec.type == "composite_harmonic") return true;
  double steps = 1;
  if (const auto* composite = dynamic_cast<const CompositeMeanValueMap*>(&map))
    steps = static_cast<double>(composite->steps());
  const double exact = steps * static_cast<double>(spec.source->size());
  return points * (exact - 70) > 0.5e6 * exact;
}

}  // namespace

MapPtr<2> make_map(const MapSpec& spec, MapCheck* check, MPI_Comm comm) {
  if (spec.type == "identity") return std::make_shared<IdentityMap<2>>();
  try {
    Stopwatch watch;
    const double cpu = process_cpu_seconds();
    MapPtr<2> map = build_map(spec);
    const double built = watch.seconds(), built_cpu = process_cpu_seconds() - cpu;
    MapCheck c = check_map(*map, spec, comm);
    c.build_seconds = watch.seconds();
    log::debug("map built in ", format_seconds(built), " (CPU ", format_seconds(built_cpu), "), checked in ",
               format_seconds(c.build_seconds - built), " (CPU ",
               format_seconds(process_cpu_seconds() - cpu - built_cpu), ", ", c.samples, " sample points)");
    // A requested certificate runs before the sampled verdict: a folding map
    // is then refused by the proof that fails, naming where.
    if (spec.certify) certify_into(*map, spec, c);
    require_passed(c, spec);
    if (check) *check = c;
    const bool automatic = spec.evaluation == "auto";
    if (spec.evaluation == "interpolated" || (automatic && interpolation_pays(*map, spec))) {
      if (automatic)
        log::info("map evaluation: interpolated (\"evaluation\": \"auto\", about ",
                  std::llround(spec.evaluation_points),
                  " quadrature points on the finest level; \"exact\" keeps the exact map)");
      InterpolantOptions o;
      o.tolerance = spec.interpolation_tolerance;
      map = with_spec_context(spec, "map.interpolation_tolerance", [&] {
        return std::make_shared<const AdaptiveInterpolant>(map, *spec.source, o, comm);
      });
    } else if (spec.evaluation != "exact" && !automatic) {
      throw Error("unknown evaluation \"" + spec.evaluation + "\"",
                  {.file = spec.origin,
                   .key_path = "map.evaluation",
                   .hint = "use \"auto\", \"exact\" or \"interpolated\""});
    }
    return map;
  } catch (const Error& e) {
    // e.g. a failed inverse while the intermediate polygon is optimized
    if (e.context().file.empty()) throw e.in_file(spec.origin);
    throw;
  }
}

}  // namespace warpfem::mapping
