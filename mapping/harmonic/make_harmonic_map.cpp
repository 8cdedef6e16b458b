#include "mapping/harmonic/make_harmonic_map.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "mapping/harmonic/intermediate_optimizer.hpp"
#include "mapping/harmonic/intermediate_polygon.hpp"
#include "mapping/polygon_sampling.hpp"
#include "mapping/spec_context.hpp"

namespace warpfem::mapping {
namespace {

std::vector<EdgeSpeed> parse_speeds(const MapSpec& spec, const std::vector<std::string>& names,
                                    const char* key) {
  return with_spec_context(spec, key, [&] {
    std::vector<EdgeSpeed> s;
    for (const auto& n : names) s.push_back(parse_edge_speed(n));
    return s;
  });
}

}  // namespace

std::shared_ptr<const CompositeHarmonicMap> make_composite_harmonic(const MapSpec& spec) {
  auto need = [&](const std::optional<Polygon>& p, const char* key) -> const Polygon& {
    if (!p)
      throw Error("map type \"" + spec.type + "\" needs a " + std::string(key + 5) + " polygon",
                  {.file = spec.origin, .key_path = key, .hint = "give a list of [x, y] vertices"});
    return *p;
  };
  const Polygon& source = need(spec.source, "map.source");
  const Polygon& target = need(spec.target, "map.target");
  with_spec_context(spec, "map.source", [&] { source.validate(); });
  with_spec_context(spec, "map.target", [&] {
    target.validate();
    require_same_vertex_count(source, target);
  });
  HarmonicOptions o;
  o.method = with_spec_context(spec, "map.harmonic_method",
                               [&] { return parse_harmonic_method(spec.harmonic_method); });
  if (spec.boundary_nodes < source.size())
    throw Error("boundary_nodes must be at least the vertex count " + std::to_string(source.size()) +
                    ", got " + std::to_string(spec.boundary_nodes),
                {.file = spec.origin, .key_path = "map.boundary_nodes", .hint = "256 is a good default"});
  if (spec.fem_max_edge_length < 0)
    throw Error("fem_max_edge_length must be positive (or 0 for automatic)",
                {.file = spec.origin, .key_path = "map.fem_max_edge_length", .hint = "e.g. 0.02"});
  o.boundary_nodes = spec.boundary_nodes;
  o.fem_max_edge_length = spec.fem_max_edge_length;
  const auto s0 = parse_speeds(spec, spec.source_edge_speeds, "map.source_edge_speeds");
  const auto s1 = parse_speeds(spec, spec.target_edge_speeds, "map.target_edge_speeds");
  with_spec_context(spec, "map.source_edge_speeds", [&] { speeds_for(source, s0); });
  with_spec_context(spec, "map.target_edge_speeds", [&] { speeds_for(target, s1); });

  Polygon lambda;
  if (spec.intermediate == "regular" || spec.intermediate == "optimized")
    lambda = regular_polygon(source.size());
  else if (spec.intermediate == "cyclic")
    lambda = with_spec_context(spec, "map.intermediate", [&] { return cyclic_intermediate(source, target); });
  else
    throw Error("unknown intermediate polygon \"" + spec.intermediate + "\"",
                {.file = spec.origin,
                 .key_path = "map.intermediate",
                 .hint = "use \"regular\", \"cyclic\" or \"optimized\""});

  // with a reused h the inverse's seed mesh matches the fem proxy's resolution
  const Real h1 = o.fem_max_edge_length > 0 ? o.fem_max_edge_length : diameter(target) / 50;
  if (spec.intermediate == "optimized") {
    HarmonicOptions fem = o;
    fem.method = HarmonicMethod::fem;
    const auto p0 =
        with_spec_context(spec, "map.source", [&] { return make_harmonic(source, lambda, s0, fem); });
    const auto p1 =
        with_spec_context(spec, "map.target", [&] { return make_harmonic(target, lambda, s1, fem); });
    IntermediateOptimizerOptions oo;
    oo.energy = spec.distortion_energy;
    const Polygon start = lambda;
    lambda = with_spec_context(spec, "map.distortion_energy",
                               [&] { return optimize_intermediate(p0, p1, oo).polygon; });
    if (o.method == HarmonicMethod::fem)
      return std::make_shared<const CompositeHarmonicMap>(p0->with_image(lambda), p1->with_image(lambda), h1);
    // the fem proxy's gain need not carry over: keep Λ' only if the requested method agrees
    const auto phi0 =
        with_spec_context(spec, "map.source", [&] { return make_harmonic(source, lambda, s0, o); });
    const auto phi1 =
        with_spec_context(spec, "map.target", [&] { return make_harmonic(target, lambda, s1, o); });
    const Points<2> sample = grid_sample(source, oo.sample_resolution);
    const Real e_opt = distortion_energy(phi0, phi1, sample, oo.energy);
    const Real e_start =
        distortion_energy(phi0->with_image(start), phi1->with_image(start), sample, oo.energy);
    if (e_opt <= e_start) return std::make_shared<const CompositeHarmonicMap>(phi0, phi1, h1);
    log::info("harmonic map: the optimized intermediate polygon does not lower the ", oo.energy,
              " distortion of the ", to_string(o.method), " map (", e_opt, " vs ", e_start, "); keeping ",
              start.name());
    return std::make_shared<const CompositeHarmonicMap>(phi0->with_image(start), phi1->with_image(start), h1);
  }
  const auto phi0 =
      with_spec_context(spec, "map.source", [&] { return make_harmonic(source, lambda, s0, o); });
  const auto phi1 =
      with_spec_context(spec, "map.target", [&] { return make_harmonic(target, lambda, s1, o); });
  return std::make_shared<const CompositeHarmonicMap>(phi0, phi1, h1);
}

MapPtr<2> make_harmonic_map(const MapSpec& spec) {
  return make_composite_harmonic(spec);
}

}  // namespace warpfem::mapping
