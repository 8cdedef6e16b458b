#pragma once
// What a config asks the mapping module to build. io/ fills it from JSON;
// make_map() turns it into a Map. Keeping this a plain struct keeps mapping/
// free of any config-format dependency.

#include <optional>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "core/polyhedron.hpp"

namespace warpfem::mapping {

struct MapSpec {
  /// "identity" or "composite_mean_value" (more types register in make_map.cpp).
  std::string type = "identity";
  /// Source Ω0 and target Ω1 (same vertex count); unused by "identity".
  std::optional<Polygon> source;
  std::optional<Polygon> target;

  // Composite mean value options (see mapping/composite_mean_value_map.hpp).
  std::string coordinates = "mean_value";  ///< mean_value | wachspress | discrete_harmonic
  std::string vertex_path = "linear";      ///< linear | intrinsic
  std::string partition = "adaptive";      ///< adaptive | greedy | uniform | explicit
  int steps = 1;                           ///< uniform: number of steps m
  std::vector<double> times;               ///< explicit: 0 = t0 < t1 < ... < tm = 1
  int sample_resolution = 64;              ///< adaptive: grid samples per bounding-box side
  double min_interval = 1e-4;              ///< adaptive: ε, smallest interval length
  double greedy_min_det = 0.2;             ///< greedy: min det J every step must keep on its sample
  int max_steps = 256;   ///< adaptive/greedy: most steps a partition may have before the pair is refused
  bool certify = false;  ///< mean value maps: prove a lower bound of det J_f (mean_value_certificate.hpp)
  // Composite harmonic options (mapping/harmonic/make_harmonic_map.hpp).
  std::string harmonic_method = "fem";   ///< fem | bem | mfs
  std::string intermediate = "regular";  ///< regular | cyclic | optimized (intermediate polygon Λ)
  int boundary_nodes = 256;              ///< bem: boundary nodes; mfs: sites (≥ vertex count)
  double fem_max_edge_length = 0;        ///< fem mesh / inverse seed mesh; 0 = bounding-box diagonal / 50
  std::string distortion_energy = "conformal";  ///< optimized: conformal | isometric
  std::vector<std::string>
      source_edge_speeds;  ///< per edge linear | quadratic | quadratic_reversed; empty = linear
  std::vector<std::string> target_edge_speeds;  ///< same, for the target's edges
  std::string origin = "map";                   ///< where this spec came from (file name) for messages
  // How f is evaluated (mapping/adaptive_interpolant.hpp).
  std::string evaluation = "auto";         ///< auto | exact | interpolated
  double interpolation_tolerance = 1e-12;  ///< f to this × diam(Ω0), J_f to 1000 × this relative
  /// Not a config key: the points at which the run will evaluate f on its finest
  /// level, estimated from the config (0: unknown); "auto" decides by it.
  double evaluation_points = 0;
};

/// The same for maps between polyhedra (mapping/polyhedron_composite_map.hpp).
struct PolyhedronMapSpec {
  std::string type = "identity";  ///< identity | composite_mean_value | composite_harmonic
  std::optional<Polyhedron> source;
  std::optional<Polyhedron> target;    ///< same triangulation as the source
  std::string vertex_path = "linear";  ///< linear | intrinsic (mapping/polyhedron_vertex_path.hpp)
  std::string partition = "adaptive";  ///< adaptive | uniform | explicit
  int steps = 1;                       ///< uniform: number of steps m
  std::vector<double> times;           ///< explicit: 0 = t0 < t1 < ... < tm = 1
  double min_det = 1e-8;               ///< adaptive: det J_k every step must exceed
  int max_halvings = 8;                ///< adaptive: halvings of an interval before refusal
  int sample_per_feature = 3;          ///< check sample: offsets per vertex, edge and face
  // Composite harmonic options (mapping/harmonic/polyhedron_harmonic_map.hpp); min_det bounds every cell's
  // det J_φ.
  double fem_max_volume = 0;       ///< TetGen volume bound in Ω0 (Ω1's scaled); 0 = |Ω0| / 5000
  double fem_quality_ratio = 2.0;  ///< TetGen radius-edge bound of both meshes
  std::string harmonic_intermediate = "auto";  ///< auto (the source if convex, else the sphere) | sphere
  std::string origin = "map";                  ///< where this spec came from (file name) for messages
};

}  // namespace warpfem::mapping
