#include "mapping/make_map.hpp"

#include <sstream>

#include "core/error.hpp"
#include "mapping/adaptive_partition.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/composite_mean_value_map.hpp"
#include "mapping/harmonic/make_harmonic_map.hpp"
#include "mapping/map_check.hpp"
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
      throw Error(
          "sample_resolution must be at least 2, got " + std::to_string(spec.sample_resolution),
          {.file = spec.origin, .key_path = "map.sample_resolution", .hint = "64 is a good default"});
    if (!(spec.min_interval > 0 && spec.min_interval < 1))
      throw Error("min_interval must lie in (0, 1)",
                  {.file = spec.origin, .key_path = "map.min_interval", .hint = "1e-4 is a good default"});
    if (!(spec.greedy_min_det > 0 && spec.greedy_min_det < 1))
      throw Error("greedy_min_det must lie in (0, 1)",
                  {.file = spec.origin, .key_path = "map.greedy_min_det", .hint = "0.2 is a good default"});
    AdaptiveOptions o;
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

}  // namespace

MapPtr<2> make_map(const MapSpec& spec, MapCheck* check) {
  if (spec.type == "identity") return std::make_shared<IdentityMap<2>>();
  try {
    MapPtr<2> map = build_map(spec);
    const MapCheck c = check_map(*map, spec);
    require_passed(c, spec);
    if (check) *check = c;
    return map;
  } catch (const Error& e) {
    // e.g. a failed inverse while the intermediate polygon is optimized
    if (e.context().file.empty()) throw e.in_file(spec.origin);
    throw;
  }
}

}  // namespace warpfem::mapping
