#pragma once
// Polygons and checks shared by the mapping tests (the polygons are those of examples/maps/*.json).

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "io/run_config.hpp"
#include "mapping/map.hpp"
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

/// Reads examples/maps/<name>.json into a MapSpec exactly as the application does.
inline MapSpec load_example(const std::string& name) {
  const std::string file = std::string(WARPFEM_SOURCE_DIR) + "/examples/maps/" + name + ".json";
  const nlohmann::json j = io::ConfigNode::parse_file(file);
  return io::parse_map_spec(io::ConfigNode(j, file).child("map"));
}

/// max over the batch of |J − central differences of f| / (1 + |J|)
inline Real jacobian_fd_error(const Map<2>& f, const Points<2>& x, Real h) {
  Jacobians<2> J;
  Points<2> fx;
  f.eval_with_jacobian(x, fx, J);
  Real worst = 0;
  for (int j = 0; j < 2; ++j) {
    Points<2> xp = x, xm = x, fp, fm;
    xp.col(j).array() += h;
    xm.col(j).array() -= h;
    f.eval(xp, fp);
    f.eval(xm, fm);
    const Points<2> fd = (fp - fm) / (2 * h);
    for (Index p = 0; p < x.rows(); ++p) {
      const Real g = 1 + jacobian_at<2>(J, p).cwiseAbs().maxCoeff();
      for (int i = 0; i < 2; ++i) worst = std::max(worst, std::abs(J(p, i * 2 + j) - fd(p, i)) / g);
    }
  }
  return worst;
}

}  // namespace warpfem::mapping::test
