#include "mapping/harmonic/spherical_intermediate.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <set>
#include <string>

#include "core/error.hpp"

namespace warpfem::mapping {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_3 cgal_point(const Point<3>& p) {
  return {p.x(), p.y(), p.z()};
}

/// Projects every vertex onto the unit sphere about the mean of the vertices.
void centre_and_project(std::vector<Point<3>>& x) {
  Point<3> c = Point<3>::Zero();
  for (const auto& p : x) c += p;
  c /= static_cast<Real>(x.size());
  for (auto& p : x) {
    const Point<3> d = p - c;
    // A vertex at the centre has no direction: keep it where it was.
    if (d.norm() > 1e-12 * (p.norm() + c.norm())) p = d.normalized();
  }
}

std::string index_list(const std::vector<Index>& items, std::size_t shown = 8) {
  std::string s;
  for (std::size_t k = 0; k < std::min(shown, items.size()); ++k)
    s += (k ? ", " : "") + std::to_string(items[k]);
  if (items.size() > shown) s += ", ... (" + std::to_string(items.size()) + " in all)";
  return s;
}

}  // namespace

std::vector<Index> non_convex_triangles(const Polyhedron& p, bool strict) {
  std::vector<Kernel::Point_3> v;
  v.reserve(p.vertices().size());
  for (const auto& q : p.vertices()) v.push_back(cgal_point(q));
  std::vector<Index> bad;
  for (Index t = 0; t < p.triangle_count(); ++t) {
    const auto& tri = p.triangle(t);
    const auto& a = v[static_cast<std::size_t>(tri[0])];
    const auto& b = v[static_cast<std::size_t>(tri[1])];
    const auto& c = v[static_cast<std::size_t>(tri[2])];
    for (Index i = 0; i < p.vertex_count(); ++i) {
      if (i == tri[0] || i == tri[1] || i == tri[2]) continue;
      // Outward triangle: the rest of a strictly convex polyhedron is on its negative side.
      const CGAL::Orientation o = CGAL::orientation(a, b, c, v[static_cast<std::size_t>(i)]);
      if (o == CGAL::POSITIVE || (strict && o == CGAL::ZERO)) {
        bad.push_back(t);
        break;
      }
    }
  }
  return bad;
}

Polyhedron spherical_intermediate(const Polyhedron& cage, int max_iterations) {
  cage.validate();
  const Index nv = cage.vertex_count(), nt = cage.triangle_count();
  const Index euler = nv - 3 * nt / 2 + nt;
  if (euler != 2)
    throw Error(cage.name() + " has genus " + std::to_string((2 - euler) / 2) +
                    ": its triangulation cannot be placed on a sphere",
                {.file = "",
                 .key_path = "",
                 .hint = "composite harmonic maps between polyhedra need a cage of genus 0 (no "
                         "handles); use \"type\": \"composite_mean_value\""});
  std::vector<std::set<Index>> neighbours(static_cast<std::size_t>(nv));
  for (const auto& t : cage.triangles())
    for (int e = 0; e < 3; ++e) {
      neighbours[static_cast<std::size_t>(t[e])].insert(t[(e + 1) % 3]);
      neighbours[static_cast<std::size_t>(t[(e + 1) % 3])].insert(t[e]);
    }
  std::vector<Point<3>> x = cage.vertices();
  centre_and_project(x);
  const std::string name = "intermediate polyhedron (spherical embedding of " + cage.name() + ")";
  std::vector<Index> bad;
  // Tested after 0, 1, 2, 4, ... steps: the central projection often suffices.
  int next_test = 0;
  for (int it = 0; it <= max_iterations; ++it) {
    if (it == next_test || it == max_iterations) {
      Polyhedron lambda(x, cage.triangles(), name);
      bad = non_convex_triangles(lambda);
      if (bad.empty()) {
        lambda.validate();
        return lambda;
      }
      next_test = std::max(1, 2 * next_test);
    }
    std::vector<Point<3>> next(x.size());
    for (Index i = 0; i < nv; ++i) {
      Point<3> mean = Point<3>::Zero();
      for (const Index j : neighbours[static_cast<std::size_t>(i)]) mean += x[static_cast<std::size_t>(j)];
      mean /= static_cast<Real>(neighbours[static_cast<std::size_t>(i)].size());
      next[static_cast<std::size_t>(i)] = 0.5 * (x[static_cast<std::size_t>(i)] + mean);
    }
    x.swap(next);
    centre_and_project(x);
  }
  throw Error(
      "the convex hull of the spherical embedding of " + cage.name() +
          " does not reproduce its triangulation after " + std::to_string(max_iterations) +
          " relaxation steps: triangles " + index_list(bad) +
          " have another vertex on or in front of their plane",
      {.file = "",
       .key_path = "",
       .hint = "retriangulate the cage so that its triangles are closer to Delaunay (flip the diagonals "
               "around those triangles, or subdivide the cage), or use \"type\": \"composite_mean_value\""});
}

}  // namespace warpfem::mapping
