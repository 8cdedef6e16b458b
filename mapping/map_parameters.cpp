#include "mapping/map_parameters.hpp"

namespace warpfem::mapping {
namespace {

ParameterTable<MapSpec> make_table() {
  ParameterTable<MapSpec> t("map");
  t.choice("type", &MapSpec::type, {"identity", "barycentric", "composite_mean_value", "composite_harmonic"},
           "the map f: Ω0 → Ω1 (`barycentric` is one mean value step and may fold)");
  t.other("source", "array of `[x, y]` or a file name", "*required*",
          "Ω0, counter-clockwise, simple; the mesh lives here. A file holds one `x, y` per line (`#` "
          "comments, blank lines); any other line, including `nan`, `inf` or a number beyond double range, "
          "is an error naming the line. Coordinates must satisfy \\|x\\|, \\|y\\| ≤ 1e30, and the bounding "
          "box must be at least 1e-30 and at least 1e-9 × the largest coordinate across, with a "
          "non-negligible area and no edge shorter than 1e-9 × the box's size");
  t.other("target", "as `source`", "required unless identity",
          "Ω1, same vertex count as `source`; vertex i of the source maps to vertex i of the target");
  t.choice("coordinates", &MapSpec::coordinates, {"mean_value", "wachspress", "discrete_harmonic"},
           "barycentric coordinates of each step (Wachspress/discrete harmonic need convex polygons)");
  t.choice("vertex_path", &MapSpec::vertex_path, {"linear", "intrinsic"},
           "how intermediate polygons move from source to target");
  t.choice("partition", &MapSpec::partition, {"adaptive", "greedy", "uniform", "explicit"},
           "the steps t0 = 0 < t1 < … < tm = 1 of the composite map. `adaptive` is the thesis' Algorithm 1 "
           "(halve every folding interval); `greedy` takes from each t the longest step whose min det J "
           "stays ≥ `greedy_min_det` (found by bisection), which usually needs fewer steps (gear: 5 instead "
           "of 7), so every evaluation of f is cheaper. Both end with the same check of the whole composite");
  t.integer("steps", &MapSpec::steps, 1, 100000, "uniform: the number of steps m");
  t.other("times", "array of numbers", "—", "explicit: the times t0 = 0, …, tm = 1");
  t.integer("sample_resolution", &MapSpec::sample_resolution, 4, 8192,
            "samples per bounding-box side for the det J check (adaptive/greedy partitions, and the fold "
            "check of every map)");
  t.number("min_interval", &MapSpec::min_interval, 1e-12, 1.0,
           "adaptive/greedy: smallest step length ε before giving up with an error");
  t.number(
      "greedy_min_det", &MapSpec::greedy_min_det, 1e-6, 0.99,
      "greedy: min det J every step keeps on its own sample, a margin against steps that barely stay "
      "bijective. Fewer steps cost distortion: on the gear, Algorithm 1 (7 steps) gives conformal "
      "distortion mean 6.2 / max 201, greedy with 0.2 (5 steps) 6.9 / 378, with 0.02 (4 steps) 8.7 / 651");
  t.integer(
      "max_steps", &MapSpec::max_steps, 1, 100000,
      "adaptive/greedy: most steps the partition may have; a pair that needs more is refused (naming "
      "the interval where it stalled). Every step costs det J checks on the full sample, so this bounds "
      "the build time of extremely distorted pairs (ε alone allows ~1/ε steps); the examples need ≤ 7");
  t.flag(
      "certify", &MapSpec::certify,
      "mean value maps (`composite_mean_value`, `barycentric`): prove a lower bound of det J_f on the whole "
      "source polygon but its vertices, with interval arithmetic on polar cells at every corner and an "
      "adaptive quadtree elsewhere, for every step's polygon (docs/maps.md). A map that cannot be certified "
      "is refused. Costs up to seconds (gear: about 2.5 s, 25 × the map build), so it is off by default; "
      "harmonic maps are never certified (sampled check only)");
  t.choice("harmonic_method", &MapSpec::harmonic_method, {"fem", "bem", "mfs"},
           "composite_harmonic: how φ0, φ1 are approximated");
  t.choice("intermediate", &MapSpec::intermediate, {"regular", "cyclic", "optimized"},
           "composite_harmonic: the convex polygon Λ");
  t.integer("boundary_nodes", &MapSpec::boundary_nodes, 3, 100000, "bem: boundary nodes; mfs: sites");
  t.number("fem_max_edge_length", &MapSpec::fem_max_edge_length, 0.0, std::numeric_limits<double>::infinity(),
           "fem: mesh size of the harmonic solve")
      .with_default("0 = bounding-box diagonal / 50");
  t.choice("distortion_energy", &MapSpec::distortion_energy, {"conformal", "isometric"},
           "optimized Λ: the energy minimized");
  for (const char* key : {"source_edge_speeds", "target_edge_speeds"})
    t.other(key, "array of `\"linear\"`, `\"quadratic\"`, `\"quadratic_reversed\"`", "all linear",
            std::string("composite_harmonic: boundary data speed per edge of the ") +
                (key[0] == 's' ? "source" : "target") + " (§5.4)");
  t.choice("evaluation", &MapSpec::evaluation, {"auto", "exact", "interpolated"},
           "`interpolated` replaces f and J_f by a quadtree of Chebyshev patches fitted to the exact map "
           "(docs/map_interpolation.md): evaluation cost independent of the vertex count; cells next to the "
           "vertices, and points outside Ω0, stay exact. The fold check always uses the exact map. `auto` "
           "interpolates when the run's quadrature points (estimated from the config) make it save "
           "more than half its build: large meshes of maps with many vertices or steps, and harmonic maps");
  t.number("interpolation_tolerance", &MapSpec::interpolation_tolerance, 1e-15, 1e-3,
           "interpolated: f within this × diam(Ω0) and J_f within 1000 × this (relative) at test points");
  return t;
}

}  // namespace

const ParameterTable<MapSpec>& map_parameters() {
  static const ParameterTable<MapSpec> table = make_table();
  return table;
}

}  // namespace warpfem::mapping
