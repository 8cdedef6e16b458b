#include "mapping/harmonic/boundary_data.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace warpfem::mapping {

EdgeSpeed parse_edge_speed(const std::string& name) {
  if (name == "linear") return EdgeSpeed::linear;
  if (name == "quadratic") return EdgeSpeed::quadratic;
  if (name == "quadratic_reversed") return EdgeSpeed::quadratic_reversed;
  throw Error(
      "unknown edge speed \"" + name + "\"",
      {.file = "", .key_path = "", .hint = "use \"linear\", \"quadratic\" or \"quadratic_reversed\""});
}

std::string to_string(EdgeSpeed speed) {
  switch (speed) {
    case EdgeSpeed::linear: return "linear";
    case EdgeSpeed::quadratic: return "quadratic";
    case EdgeSpeed::quadratic_reversed: return "quadratic_reversed";
  }
  return "?";
}

Real edge_speed(EdgeSpeed speed, Real t) {
  switch (speed) {
    case EdgeSpeed::linear: return t;
    case EdgeSpeed::quadratic: return t * t;
    case EdgeSpeed::quadratic_reversed: return 1 - (1 - t) * (1 - t);
  }
  return t;
}

std::vector<EdgeSpeed> speeds_for(const Polygon& domain, const std::vector<EdgeSpeed>& speeds) {
  if (speeds.empty())
    return std::vector<EdgeSpeed>(static_cast<std::size_t>(domain.size()), EdgeSpeed::linear);
  if (static_cast<Index>(speeds.size()) != domain.size())
    throw Error("harmonic map: " + std::to_string(speeds.size()) + " edge speeds for the " +
                    std::to_string(domain.size()) + " edges of " + domain.name(),
                {.file = "", .key_path = "", .hint = "give one speed per edge, or none for all linear"});
  return speeds;
}

namespace {
BoundaryNodes split_edges(const Polygon& domain, const std::vector<Index>& segments) {
  BoundaryNodes nodes;
  for (Index i = 0; i < domain.size(); ++i) {
    const Index k = segments[static_cast<std::size_t>(i)];
    for (Index j = 0; j < k; ++j) {
      const Real t = static_cast<Real>(j) / static_cast<Real>(k);
      nodes.x.push_back((1 - t) * domain.vertex(i) + t * domain.vertex(i + 1));
      nodes.at.push_back({i, t});
    }
  }
  return nodes;
}
}  // namespace

BoundaryNodes sample_boundary(const Polygon& domain, Index count) {
  const Real P = domain.perimeter();
  std::vector<Index> segments;
  for (Index i = 0; i < domain.size(); ++i) {
    const Real L = (domain.vertex(i + 1) - domain.vertex(i)).norm();
    segments.push_back(std::max<Index>(1, std::llround(static_cast<Real>(count) * L / P)));
  }
  return split_edges(domain, segments);
}

BoundaryNodes subdivide_boundary(const Polygon& domain, Real max_length) {
  require(max_length > 0, "harmonic map: the boundary element length must be positive");
  std::vector<Index> segments;
  for (Index i = 0; i < domain.size(); ++i) {
    const Real L = (domain.vertex(i + 1) - domain.vertex(i)).norm();
    segments.push_back(std::max<Index>(1, static_cast<Index>(std::ceil(L / max_length - 1e-9))));
  }
  return split_edges(domain, segments);
}

void boundary_weights(const std::vector<EdgeSpeed>& speeds, const BoundaryPoint& p, Real* weights, Index n) {
  std::fill(weights, weights + n, Real{0});
  const Real s = edge_speed(speeds[static_cast<std::size_t>(p.edge)], p.t);
  weights[p.edge] += 1 - s;
  weights[(p.edge + 1) % n] += s;
}

Point<2> boundary_value(const Polygon& image, const std::vector<EdgeSpeed>& speeds, const BoundaryPoint& p) {
  const Real s = edge_speed(speeds[static_cast<std::size_t>(p.edge)], p.t);
  return (1 - s) * image.vertex(p.edge) + s * image.vertex(p.edge + 1);
}

BoundaryPoint closest_boundary_point(const Polygon& domain, const Point<2>& x, Real* distance) {
  BoundaryPoint best;
  Real best_d2 = std::numeric_limits<Real>::infinity();
  for (Index i = 0; i < domain.size(); ++i) {
    const Point<2> a = domain.vertex(i), e = domain.vertex(i + 1) - a;
    const Real t = std::clamp((x - a).dot(e) / e.squaredNorm(), Real{0}, Real{1});
    const Real d2 = (a + t * e - x).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = {i, t};
    }
  }
  if (distance) *distance = std::sqrt(best_d2);
  return best;
}

std::vector<std::optional<BoundaryPoint>> boundary_points(const Mesh<2>& mesh, const Polygon& domain) {
  std::vector<std::optional<BoundaryPoint>> at(static_cast<std::size_t>(mesh.num_vertices()));
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f)
    for (Index k = 0; k < mesh.boundary_facets.cols(); ++k) {
      const Index v = mesh.boundary_facets(f, k);
      auto& p = at[static_cast<std::size_t>(v)];
      if (!p) p = closest_boundary_point(domain, mesh.vertex(v), nullptr);
    }
  return at;
}

Point<2> boundary_position(const Polygon& domain, const BoundaryPoint& p) {
  return (1 - p.t) * domain.vertex(p.edge) + p.t * domain.vertex(p.edge + 1);
}

Real diameter(const Polygon& polygon) {
  return (polygon.bbox_max() - polygon.bbox_min()).norm();
}

}  // namespace warpfem::mapping
