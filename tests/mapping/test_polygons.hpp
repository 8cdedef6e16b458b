#pragma once
// Polygons shared by the mapping tests (the same ones as examples/maps/*.json).

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::mapping::test {

inline Polygon polygon(std::vector<Point<2>> v, std::string name) {
  return Polygon::checked(std::move(v), name);
}

/// The square of thesis §2.1.2 (a diamond with v1 = −v3) and its dart with v3 pulled to (x, 0).
inline Polygon diamond() {
  return polygon({{-1, 0}, {0, -1}, {1, 0}, {0, 1}}, "diamond");
}
inline Polygon dart(Real x = -0.6) {
  return polygon({{-1, 0}, {0, -1}, {x, 0}, {0, 1}}, "dart");
}

/// Five-pointed star (10 vertices); `bend` rotates the tips (a pinwheel star).
inline Polygon star(Real bend = 0, Real inner = 0.4) {
  std::vector<Point<2>> v;
  for (int i = 0; i < 10; ++i) {
    const Real r = i % 2 == 0 ? 1.0 : inner;
    const Real a = std::numbers::pi / 2 + i * std::numbers::pi / 5 + (i % 2 == 0 ? bend : 0.0);
    v.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return polygon(v, bend == 0 ? "star" : "bent star");
}

/// An irregular concave 32-gon (star-shaped w.r.t. the origin), the benchmark polygon.
inline Polygon concave32() {
  std::vector<Point<2>> v;
  for (int i = 0; i < 32; ++i) {
    const Real a = 2 * std::numbers::pi * i / 32;
    const Real r = 1.0 + 0.35 * std::sin(3 * a) + (i % 2 ? -0.25 : 0.0);
    v.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return polygon(v, "concave 32-gon");
}

/// A convex, irregular hexagon.
inline Polygon convex6() {
  return polygon({{0, 0}, {2, -0.3}, {3.1, 0.8}, {2.7, 2.2}, {1.0, 2.6}, {-0.6, 1.3}}, "convex hexagon");
}

/// Reads examples/maps/<name>.json into a MapSpec (what io/ will do).
inline MapSpec load_example(const std::string& name) {
  const std::string file = std::string(WARPFEM_SOURCE_DIR) + "/examples/maps/" + name + ".json";
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in).at("map");
  auto poly = [&](const char* key) {
    std::vector<Point<2>> v;
    for (const auto& p : j.at(key)) v.emplace_back(p.at(0).get<Real>(), p.at(1).get<Real>());
    return Polygon(v, name + " " + key);
  };
  MapSpec s;
  s.type = j.at("type");
  s.source = poly("source");
  s.target = poly("target");
  s.vertex_path = j.value("vertex_path", s.vertex_path);
  s.partition = j.value("partition", s.partition);
  s.steps = j.value("steps", s.steps);
  s.sample_resolution = j.value("sample_resolution", s.sample_resolution);
  s.min_interval = j.value("min_interval", s.min_interval);
  if (j.contains("times")) s.times = j.at("times").get<std::vector<Real>>();
  s.origin = file;
  return s;
}

}  // namespace warpfem::mapping::test
