#include "fem/hierarchy/polyhedron_parts.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

#include "core/error.hpp"

namespace warpfem::fem {
namespace {

Point<3> area_normal(const Polyhedron& p, Index t) {
  const auto& [a, b, c] = p.triangle(t);
  return (p.vertex(b) - p.vertex(a)).cross(p.vertex(c) - p.vertex(a));
}

/// Euclidean distance from x to triangle t.
double distance_to_triangle(const Polyhedron& p, Index t, const Point<3>& x) {
  const auto& tri = p.triangle(t);
  const Point<3> a = p.vertex(tri[0]), b = p.vertex(tri[1]), c = p.vertex(tri[2]);
  const Point<3> n = (b - a).cross(c - a).normalized();
  const double height = std::abs((x - a).dot(n));
  const Point<3> y = x - (x - a).dot(n) * n;  // projection onto the plane
  // Inside if y is on the inner side of each edge (with the triangle's orientation).
  double outside = 0;
  const Point<3> v[3] = {a, b, c};
  for (int e = 0; e < 3; ++e) {
    const Point<3> p0 = v[e], p1 = v[(e + 1) % 3];
    const Point<3> inward = n.cross(p1 - p0).normalized();
    outside = std::max(outside, -(y - p0).dot(inward));
  }
  return std::hypot(height, outside);
}

}  // namespace

PolyhedronParts planar_face_groups(const Polyhedron& p) {
  const std::size_t nt = p.triangles().size();
  // Triangles sharing an edge, through a map from the sorted vertex pair.
  std::map<std::pair<Index, Index>, std::vector<Index>> edge_triangles;
  for (Index t = 0; t < p.triangle_count(); ++t)
    for (int e = 0; e < 3; ++e) {
      Index a = p.triangle(t)[static_cast<std::size_t>(e)],
            b = p.triangle(t)[static_cast<std::size_t>((e + 1) % 3)];
      if (a > b) std::swap(a, b);
      edge_triangles[{a, b}].push_back(t);
    }
  std::vector<Point<3>> unit(nt);
  for (std::size_t t = 0; t < nt; ++t) unit[t] = area_normal(p, static_cast<Index>(t)).normalized();

  PolyhedronParts parts;
  parts.triangle_part = std::vector<int>(nt, -1);
  for (Index seed = 0; seed < p.triangle_count(); ++seed) {
    if (parts.triangle_part[static_cast<std::size_t>(seed)] >= 0) continue;
    const int part = parts.count();
    const Point<3> n = unit[static_cast<std::size_t>(seed)];
    Point<3> weighted = Point<3>::Zero();
    double area = 0;
    std::vector<Index> stack = {seed};
    parts.triangle_part[static_cast<std::size_t>(seed)] = part;
    while (!stack.empty()) {
      const Index t = stack.back();
      stack.pop_back();
      const auto& tri = p.triangle(t);
      const double a = 0.5 * area_normal(p, t).norm();
      weighted += a * (p.vertex(tri[0]) + p.vertex(tri[1]) + p.vertex(tri[2])) / 3.0;
      area += a;
      for (int e = 0; e < 3; ++e) {
        Index u = tri[static_cast<std::size_t>(e)], v = tri[static_cast<std::size_t>((e + 1) % 3)];
        if (u > v) std::swap(u, v);
        for (Index s : edge_triangles[{u, v}]) {
          auto& sp = parts.triangle_part[static_cast<std::size_t>(s)];
          // Neighbours across an edge lie in one plane iff their normals agree.
          if (sp < 0 && unit[static_cast<std::size_t>(s)].dot(n) > 1 - 1e-12) {
            sp = part;
            stack.push_back(s);
          }
        }
      }
    }
    parts.normal.push_back(n);
    parts.centroid.push_back(weighted / area);
  }
  return parts;
}

PolyhedronParts boundary_parts(const Polyhedron& p) {
  if (p.triangle_parts().empty()) return planar_face_groups(p);
  PolyhedronParts parts;
  parts.given = true;
  parts.triangle_part = p.triangle_parts();
  const int count = *std::max_element(parts.triangle_part.begin(), parts.triangle_part.end()) + 1;
  std::vector<Point<3>> area_normal_sum(static_cast<std::size_t>(count), Point<3>::Zero());
  std::vector<Point<3>> weighted(static_cast<std::size_t>(count), Point<3>::Zero());
  std::vector<double> area(static_cast<std::size_t>(count), 0.0);
  for (Index t = 0; t < p.triangle_count(); ++t) {
    const auto k = static_cast<std::size_t>(parts.triangle_part[static_cast<std::size_t>(t)]);
    const auto& tri = p.triangle(t);
    const Point<3> n = area_normal(p, t);
    area_normal_sum[k] += n;
    area[k] += 0.5 * n.norm();
    weighted[k] += 0.5 * n.norm() * (p.vertex(tri[0]) + p.vertex(tri[1]) + p.vertex(tri[2])) / 3.0;
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(count); ++k) {
    // A closed part (the whole surface) has no mean normal; zero says so.
    const double norm = area_normal_sum[k].norm();
    parts.normal.push_back(norm > 1e-12 * area[k] ? Point<3>(area_normal_sum[k] / norm) : Point<3>::Zero());
    parts.centroid.push_back(weighted[k] / area[k]);
  }
  return parts;
}

void tag_facets_by_part(Mesh<3>& mesh, const Polyhedron& p, const PolyhedronParts& parts) {
  const double tolerance = 1e-9 * (p.bbox_max() - p.bbox_min()).norm();
  mesh.facet_tags.assign(static_cast<std::size_t>(mesh.num_boundary_facets()), -1);
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f) {
    Point<3> centroid = Point<3>::Zero();
    const auto corners = mesh.boundary_facets.cols();
    for (Index k = 0; k < corners; ++k) centroid += mesh.vertex(mesh.boundary_facets(f, k));
    centroid /= static_cast<double>(corners);
    Index best = -1;
    double best_distance = tolerance;
    for (Index t = 0; t < p.triangle_count(); ++t)
      if (const double d = distance_to_triangle(p, t, centroid); d <= best_distance) {
        best = t;
        best_distance = d;
      }
    if (best < 0)
      throw Error("boundary facet " + std::to_string(f) + " of the mesh (centroid " +
                      std::to_string(centroid.x()) + ", " + std::to_string(centroid.y()) + ", " +
                      std::to_string(centroid.z()) + ") lies on no triangle of " + p.name(),
                  {.file = "", .key_path = "", .hint = "mesh the source polyhedron itself"});
    mesh.facet_tags[static_cast<std::size_t>(f)] = parts.triangle_part[static_cast<std::size_t>(best)];
  }
}

}  // namespace warpfem::fem
