#pragma once
// Configs of maps between polyhedra: "map" objects whose source is a
// polyhedron, given inline as {"vertices": [[x, y, z], ...], "triangles":
// [[i, j, k], ...]} (0-based, outward) or as {"file": "cage.off"} (OFF, OBJ,
// STL or PLY, relative to the config's directory).

#include <string>

#include "core/polyhedron.hpp"
#include "io/config_node.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::io {

/// True when `root` has a "map" whose "source" is a polyhedron (a JSON object).
bool is_polyhedron_map(const nlohmann::json& root);

/// The polyhedron stored at `key`, validated; errors name the config (or the
/// surface file) and the field. With `boundary_parts` (the source), an optional
/// "face_parts" gives each triangle's boundary part: an array of ids, one per
/// triangle, or "groups" for the g groups of an OBJ file.
Polyhedron parse_polyhedron(const ConfigNode& node, const std::string& key, const std::string& name,
                            bool boundary_parts = false);

/// Reads a "map" object between polyhedra.
mapping::PolyhedronMapSpec parse_polyhedron_map_spec(const ConfigNode& node);

}  // namespace warpfem::io
