#pragma once
// Helpers shared by the harmonic-map tests.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/polygon.hpp"
#include "mapping/map.hpp"
#include "mapping/map_spec.hpp"

namespace warpfem::mapping::test {

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

/// Points of `x` at least `margin` inside polygon (distance to every edge).
inline Points<2> keep_away_from_boundary(const Points<2>& x, const Polygon& P, Real margin) {
  std::vector<Index> keep;
  for (Index p = 0; p < x.rows(); ++p) {
    Real d = 1e300;
    for (Index i = 0; i < P.size(); ++i) {
      const Point<2> a = P.vertex(i), e = P.vertex(i + 1) - a, q = x.row(p).transpose();
      const Real t = std::clamp((q - a).dot(e) / e.squaredNorm(), Real{0}, Real{1});
      d = std::min(d, (a + t * e - q).norm());
    }
    if (d >= margin) keep.push_back(p);
  }
  Points<2> out(static_cast<Index>(keep.size()), 2);
  for (std::size_t k = 0; k < keep.size(); ++k) out.row(static_cast<Index>(k)) = x.row(keep[k]);
  return out;
}

/// Reads examples/maps/<name>.json with the composite harmonic keys into a
/// MapSpec (what io/ does for "composite_harmonic").
inline MapSpec load_harmonic_example(const std::string& name) {
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
  s.harmonic_method = j.value("harmonic_method", s.harmonic_method);
  s.intermediate = j.value("intermediate", s.intermediate);
  s.boundary_nodes = j.value("boundary_nodes", s.boundary_nodes);
  s.fem_max_edge_length = j.value("fem_max_edge_length", s.fem_max_edge_length);
  s.distortion_energy = j.value("distortion_energy", s.distortion_energy);
  s.source_edge_speeds = j.value("source_edge_speeds", s.source_edge_speeds);
  s.target_edge_speeds = j.value("target_edge_speeds", s.target_edge_speeds);
  s.origin = file;
  return s;
}

}  // namespace warpfem::mapping::test
