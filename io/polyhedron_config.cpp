#include "io/polyhedron_config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "core/log.hpp"
#include "core/obj_face_groups.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

bool is_polyhedron_map(const nlohmann::json& root) {
  if (!root.is_object()) return false;
  const auto map = root.find("map");
  if (map == root.end() || !map->is_object()) return false;
  const auto source = map->find("source");
  return source != map->end() && source->is_object();
}

namespace {

std::vector<Point<3>> parse_vertices(const ConfigNode& node) {
  const nlohmann::json& v = node.raw("vertices");
  if (!v.is_array() || v.size() < 4)
    throw node.error("vertices",
                     "expected an array of at least four [x, y, z] vertices, got " + json_excerpt(v));
  std::vector<Point<3>> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& p = v[i];
    const bool ok = p.is_array() && p.size() == 3 && p[0].is_number() && p[1].is_number() && p[2].is_number();
    if (!ok || !std::isfinite(p[0].get<double>()) || !std::isfinite(p[1].get<double>()) ||
        !std::isfinite(p[2].get<double>()))
      throw node.error("vertices/" + std::to_string(i),
                       "expected a vertex [x, y, z] of finite numbers, got " + json_excerpt(p));
    out.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  }
  return out;
}

std::vector<Polyhedron::Triangle> parse_triangles(const ConfigNode& node, std::size_t vertices) {
  const nlohmann::json& t = node.raw("triangles");
  if (!t.is_array() || t.size() < 4)
    throw node.error("triangles",
                     "expected an array of at least four [i, j, k] triangles, got " + json_excerpt(t));
  std::vector<Polyhedron::Triangle> out;
  for (std::size_t f = 0; f < t.size(); ++f) {
    const auto& tri = t[f];
    Polyhedron::Triangle ijk{};
    bool ok = tri.is_array() && tri.size() == 3;
    for (std::size_t k = 0; ok && k < 3; ++k) {
      ok = tri[k].is_number_unsigned() && tri[k].get<std::uint64_t>() < vertices;
      if (ok) ijk[k] = static_cast<Index>(tri[k].get<std::uint64_t>());
    }
    if (!ok)
      throw node.error(
          "triangles/" + std::to_string(f),
          "expected three vertex indices in [0, " + std::to_string(vertices) + "), got " + json_excerpt(tri),
          "indices are 0-based into \"vertices\"");
    out.push_back(ijk);
  }
  return out;
}

/// "face_parts": one boundary-part id per triangle, or "groups" (the g groups
/// of an OBJ file, `obj_path`; empty for an inline surface).
std::vector<int> parse_face_parts(const ConfigNode& node, Index triangles, const std::string& obj_path,
                                  const std::string& surface) {
  const nlohmann::json& f = node.raw("face_parts");
  if (f.is_string() && f.get<std::string>() == "groups") {
    if (obj_path.empty())
      throw node.error("face_parts",
                       "\"groups\" reads the g groups of an OBJ file, but " + surface + " has no groups",
                       "list one part id per triangle, e.g. \"face_parts\": [0, 0, 1, 1, ...]");
    const ObjFaceGroups groups = read_obj_face_groups(obj_path);
    if (static_cast<Index>(groups.face_group.size()) != triangles)
      throw node.error("face_parts",
                       surface + " has " + std::to_string(groups.face_group.size()) +
                           " faces in its groups but " + std::to_string(triangles) + " triangles were read",
                       "write one \"f\" line per triangle");
    std::string listing;
    for (std::size_t k = 0; k < groups.names.size(); ++k)
      listing += (k ? ", " : "") + std::to_string(k) + " = \"" + groups.names[k] + "\"";
    log::info(surface, ": boundary parts from the file's groups: ", listing);
    return groups.face_group;
  }
  if (!f.is_array())
    throw node.error(
        "face_parts",
        "expected an array of boundary-part ids (one per triangle)" +
            std::string(obj_path.empty() ? "" : " or \"groups\" (the OBJ file's g groups)") + ", got " +
            json_excerpt(f),
        "e.g. \"face_parts\": [0, 0, 1, 1, ...]; \"faces\" of boundary conditions name these ids");
  if (static_cast<Index>(f.size()) != triangles)
    throw node.error("face_parts",
                     std::to_string(f.size()) + " part ids for the " + std::to_string(triangles) +
                         " triangles of " + surface,
                     "give one part id per triangle, in the order of the triangles");
  std::vector<int> parts;
  for (std::size_t t = 0; t < f.size(); ++t) {
    if (!f[t].is_number_unsigned() || f[t].get<std::uint64_t>() >= static_cast<std::uint64_t>(triangles))
      throw node.error("face_parts/" + std::to_string(t),
                       "expected a part id in [0, " + std::to_string(triangles - 1) + "] for triangle " +
                           std::to_string(t) + ", got " + json_excerpt(f[t]),
                       "number the parts 0, 1, ..., K-1");
    parts.push_back(f[t].get<int>());
  }
  return parts;
}

/// Sets the parts the config gave; errors name "face_parts".
void set_face_parts(Polyhedron& p, const ConfigNode& node, std::vector<int> parts) {
  try {
    p.set_triangle_parts(std::move(parts));
  } catch (const Error& e) {
    throw node.error("face_parts", e.message(), e.context().hint);
  }
}

}  // namespace

Polyhedron parse_polyhedron(const ConfigNode& parent, const std::string& key, const std::string& name,
                            bool boundary_parts) {
  const nlohmann::json& raw = parent.raw(key);
  if (!raw.is_object())
    throw parent.error(key,
                       "expected a polyhedron {\"vertices\": [...], \"triangles\": [...]} or {\"file\": ...}",
                       "the source is a polyhedron, so the target must be one too");
  const ConfigNode node = parent.child(key);
  if (node.has("face_parts") && !boundary_parts)
    throw node.error("face_parts",
                     "boundary parts belong to the source polyhedron; the " + name + " takes its triangles",
                     "move \"face_parts\" to \"source\"");
  if (node.has("file")) {
    fs::path p(node.get_string("file", ""));
    if (p.is_relative()) p = fs::path(parent.file()).parent_path() / p;
    const Polyhedron read = [&] {
      try {
        return Polyhedron::read(p.string());
      } catch (const Error& e) {
        // The file is named; the field says which polyhedron it is.
        throw Error(e.message(),
                    {.file = e.context().file, .key_path = node.path_of("file"), .hint = e.context().hint});
      }
    }();
    Polyhedron out(read.vertices(), read.triangles(), name + " (" + p.filename().string() + ")");
    if (node.has("face_parts")) {
      std::string ext = p.extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
      set_face_parts(out, node,
                     parse_face_parts(node, out.triangle_count(), ext == ".obj" ? p.string() : "",
                                      p.filename().string()));
    }
    node.finish();
    return out;
  }
  if (!node.has("vertices") || !node.has("triangles"))
    throw node.error(
        "", "a polyhedron needs \"vertices\" and \"triangles\" (or a \"file\")",
        "add \"vertices\": [[x, y, z], ...], \"triangles\": [[i, j, k], ...] (0-based, outward)");
  const std::vector<Point<3>> v = parse_vertices(node);
  std::vector<Polyhedron::Triangle> t = parse_triangles(node, v.size());
  std::vector<int> parts;
  if (node.has("face_parts")) parts = parse_face_parts(node, static_cast<Index>(t.size()), "", "the surface");
  Polyhedron out = [&] {
    try {
      return Polyhedron::checked(v, std::move(t), name);
    } catch (const Error& e) {
      throw Error(e.message(),
                  {.file = parent.file(), .key_path = parent.path_of(key), .hint = e.context().hint});
    }
  }();
  if (!parts.empty()) set_face_parts(out, node, std::move(parts));
  node.finish();
  return out;
}

mapping::PolyhedronMapSpec parse_polyhedron_map_spec(const ConfigNode& node) {
  mapping::PolyhedronMapSpec spec;
  spec.origin = node.file();
  spec.type = node.get_choice("type", "identity", {"identity", "composite_mean_value", "composite_harmonic"});
  spec.source = parse_polyhedron(node, "source", "source polyhedron", true);
  if (spec.type != "identity") {
    if (!node.has("target"))
      throw node.error("target",
                       "missing required field: the target polyhedron Ω1 for map type \"" + spec.type + "\"",
                       "add \"target\" with the source's triangles and moved vertices");
    spec.target = parse_polyhedron(node, "target", "target polyhedron");
    try {
      require_same_triangulation(*spec.source, *spec.target);
    } catch (const Error& e) {
      throw node.error("target", e.message(), e.context().hint);
    }
  } else if (node.has("target")) {
    throw node.error("target", "the identity map takes no target polyhedron",
                     "remove \"target\" or set \"type\": \"composite_mean_value\"");
  }
  spec.vertex_path = node.get_choice("vertex_path", spec.vertex_path, {"linear", "intrinsic"});
  spec.partition = node.get_choice("partition", spec.partition, {"adaptive", "uniform", "explicit"});
  spec.steps = static_cast<int>(node.get_int("steps", spec.steps, 1, 100000));
  spec.times = node.get_doubles("times");
  spec.min_det = node.get_double("min_det", spec.min_det, 1e-14, 0.99);
  spec.max_halvings = static_cast<int>(node.get_int("max_halvings", spec.max_halvings, 0, 30));
  spec.sample_per_feature =
      static_cast<int>(node.get_int("sample_per_feature", spec.sample_per_feature, 1, 4));
  spec.fem_max_volume = node.get_double("fem_max_volume", spec.fem_max_volume, 0.0);
  // TetGen and the direct solve of the harmonic maps grow with |Ω0| / fem_max_volume.
  if (const double smallest = 1e-7 * std::abs(spec.source->signed_volume());
      spec.fem_max_volume > 0 && spec.fem_max_volume < smallest)
    throw node.error(
        "fem_max_volume",
        "a volume bound of " + std::to_string(spec.fem_max_volume) +
            " asks for more than ten million tetrahedra in the source",
        "give at least " + std::to_string(smallest) + " (1e-7 of the source's volume), or 0 for |Ω0| / 5000");
  spec.fem_quality_ratio = node.get_double("fem_quality_ratio", spec.fem_quality_ratio, 1.2, 100.0);
  spec.harmonic_intermediate =
      node.get_choice("intermediate", spec.harmonic_intermediate, {"auto", "sphere"});
  if (spec.partition == "explicit" && spec.times.empty())
    throw node.error("times", "the explicit partition needs \"times\"", "give 0 = t0 < t1 < ... < tm = 1");
  node.finish();
  return spec;
}

}  // namespace warpfem::io
