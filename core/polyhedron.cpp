#include "core/polyhedron.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <utility>

#include "core/error.hpp"

namespace warpfem {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KPoint = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<KPoint>;
namespace PMP = CGAL::Polygon_mesh_processing;

// Same limits as for polygons: products of coordinate differences must stay
// representable, and the surface must be resolvable in double precision.
constexpr double kMaxCoordinate = 1e30;
constexpr double kMinExtent = 1e-30;
constexpr double kMinRelativeExtent = 1e-9;
/// Shortest edge / bounding-box size, as for polygons: shorter edges are not
/// resolved by the coordinates' differences in the maps' products.
constexpr double kMinRelativeEdge = 1e-9;

KPoint to_cgal(const Point<3>& p) {
  return KPoint(p.x(), p.y(), p.z());
}

std::string number_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

std::string point_text(const Point<3>& p) {
  return "(" + number_text(p.x()) + ", " + number_text(p.y()) + ", " + number_text(p.z()) + ")";
}

std::string triangle_text(const Polyhedron::Triangle& t) {
  return "(" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")";
}

Error failure(const std::string& message, const std::string& hint) {
  return Error(message, {.file = "", .key_path = "", .hint = hint});
}

/// The triangles around vertex v must form one closed fan: walking from
/// triangle to triangle across the edges at v must visit all of them.
bool single_fan(Index v, const std::vector<Index>& around,
                const std::vector<Polyhedron::Triangle>& triangles) {
  // Map "next vertex after v" -> triangle; each triangle (v, a, b) leads from a to b.
  std::map<Index, Index> from;
  for (const Index t : around) {
    const auto& tr = triangles[static_cast<std::size_t>(t)];
    const int k = tr[0] == v ? 0 : (tr[1] == v ? 1 : 2);
    from[tr[(k + 1) % 3]] = tr[(k + 2) % 3];
  }
  Index a = from.begin()->first;
  std::size_t steps = 0;
  do {
    auto it = from.find(a);
    if (it == from.end()) return false;
    a = it->second;
    ++steps;
  } while (a != from.begin()->first && steps <= around.size());
  return steps == around.size();
}

}  // namespace

Polyhedron::Polyhedron(std::vector<Point<3>> vertices, std::vector<Triangle> triangles, std::string name)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)), name_(std::move(name)) {}

Polyhedron Polyhedron::checked(std::vector<Point<3>> vertices, std::vector<Triangle> triangles,
                               std::string name) {
  Polyhedron p(std::move(vertices), std::move(triangles), std::move(name));
  p.validate();
  return p;
}

Polyhedron Polyhedron::read(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw Error(
        "cannot open the surface file",
        {.file = path, .key_path = "", .hint = "give the path of an existing .off, .obj, .stl or .ply file"});
  std::vector<KPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  if (!CGAL::IO::read_polygon_soup(path, points, polygons) || points.empty())
    throw Error("cannot read a surface from this file",
                {.file = path,
                 .key_path = "",
                 .hint = "write the surface as a triangle mesh in OFF, OBJ, STL or PLY format"});
  std::vector<Point<3>> v;
  v.reserve(points.size());
  for (const auto& p : points) v.emplace_back(p.x(), p.y(), p.z());
  std::vector<Triangle> t;
  t.reserve(polygons.size());
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    if (polygons[f].size() != 3)
      throw Error(
          "face " + std::to_string(f) + " has " + std::to_string(polygons[f].size()) + " vertices",
          {.file = path, .key_path = "", .hint = "triangulate the surface (every face must be a triangle)"});
    t.push_back({static_cast<Index>(polygons[f][0]), static_cast<Index>(polygons[f][1]),
                 static_cast<Index>(polygons[f][2])});
  }
  try {
    return checked(std::move(v), std::move(t), std::filesystem::path(path).filename().string());
  } catch (const Error& e) {
    throw e.in_file(path);
  }
}

void Polyhedron::set_triangle_parts(std::vector<int> parts) {
  if (static_cast<Index>(parts.size()) != triangle_count())
    throw failure(name_ + ": " + std::to_string(parts.size()) + " boundary-part ids for " +
                      std::to_string(triangle_count()) + " triangles",
                  "give one part id per triangle, in the order of the triangles");
  std::vector<bool> used;
  for (std::size_t t = 0; t < parts.size(); ++t) {
    if (parts[t] < 0 || static_cast<std::size_t>(parts[t]) >= parts.size())
      throw failure(name_ + ": triangle " + std::to_string(t) + " has the part id " +
                        std::to_string(parts[t]) + ", outside [0, " + std::to_string(parts.size() - 1) + "]",
                    "number the parts 0, 1, ..., K-1 (at most one part per triangle)");
    if (static_cast<std::size_t>(parts[t]) >= used.size())
      used.resize(static_cast<std::size_t>(parts[t]) + 1);
    used[static_cast<std::size_t>(parts[t])] = true;
  }
  for (std::size_t k = 0; k < used.size(); ++k)
    if (!used[k])
      throw failure(name_ + ": part " + std::to_string(k) + " has no triangle, but part " +
                        std::to_string(used.size() - 1) + " has",
                    "number the parts 0, 1, ..., K-1 without gaps");
  triangle_parts_ = std::move(parts);
}

void Polyhedron::validate() const {
  const Index n = vertex_count(), m = triangle_count();
  if (n < 4 || m < 4)
    throw failure(name_ + " has " + std::to_string(n) + " vertices and " + std::to_string(m) + " triangles",
                  "a closed triangulated surface needs at least 4 vertices and 4 triangles");
  for (Index i = 0; i < n; ++i) {
    if (!vertex(i).allFinite())
      throw failure(name_ + ": vertex " + std::to_string(i) + " is not a finite number",
                    "give finite coordinates");
    if (vertex(i).cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw failure(name_ + ": vertex " + std::to_string(i) + " " + point_text(vertex(i)) +
                        " lies beyond the supported coordinate range " + number_text(kMaxCoordinate),
                    "rescale the polyhedron (choose other length units)");
  }
  const Point<3> extent = bbox_max() - bbox_min();
  const double size = extent.maxCoeff();
  const double magnitude = std::max(bbox_max().cwiseAbs().maxCoeff(), bbox_min().cwiseAbs().maxCoeff());
  if (size < kMinExtent || size < kMinRelativeExtent * magnitude)
    throw failure(name_ + " is degenerate or too small: its bounding box is " + number_text(extent.x()) +
                      " x " + number_text(extent.y()) + " x " + number_text(extent.z()) +
                      " at coordinates up to " + number_text(magnitude),
                  "rescale the polyhedron or move it nearer the origin");

  // Combinatorics: indices, degenerate index triples, closed 2-manifold edges
  // with consistent orientation, every vertex used, one fan per vertex.
  std::map<std::pair<Index, Index>, std::vector<Index>> directed;  // (a, b) -> triangles with edge a -> b
  std::vector<std::vector<Index>> around(static_cast<std::size_t>(n));
  for (Index t = 0; t < m; ++t) {
    const Triangle& tr = triangle(t);
    for (const Index v : tr)
      if (v < 0 || v >= n)
        throw failure(name_ + ": triangle " + std::to_string(t) + " " + triangle_text(tr) +
                          " refers to vertex " + std::to_string(v) + " but there are " + std::to_string(n) +
                          " vertices",
                      "vertex indices run from 0 to the vertex count minus one");
    if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2])
      throw failure(name_ + ": triangle " + std::to_string(t) + " " + triangle_text(tr) + " repeats a vertex",
                    "remove the triangle or give it three distinct vertices");
    for (int k = 0; k < 3; ++k) {
      directed[{tr[k], tr[(k + 1) % 3]}].push_back(t);
      around[static_cast<std::size_t>(tr[k])].push_back(t);
    }
  }
  for (const auto& [edge, ts] : directed) {
    const std::string edge_text = std::to_string(edge.first) + "-" + std::to_string(edge.second);
    const auto twin = directed.find({edge.second, edge.first});
    const std::size_t uses = ts.size() + (twin == directed.end() ? 0 : twin->second.size());
    if (uses > 2)
      throw failure(
          name_ + " is not 2-manifold: " + std::to_string(uses) + " triangles share edge " + edge_text +
              " (triangles " + std::to_string(ts[0]) + " and " + std::to_string(ts[1]) + " among them)",
          "every edge must belong to exactly two triangles: remove the extra triangles or split the edge");
    if (ts.size() > 1)
      throw failure(
          name_ + ": triangles " + std::to_string(ts[0]) + " " + triangle_text(triangle(ts[0])) + " and " +
              std::to_string(ts[1]) + " " + triangle_text(triangle(ts[1])) + " both run along edge " +
              edge_text + " in the same direction",
          "the orientation is inconsistent: reverse the orientation of one of them (swap two of its "
          "vertex indices)");
    if (twin == directed.end())
      throw failure(name_ + " is not closed: edge " + edge_text + " of triangle " + std::to_string(ts[0]) +
                        " belongs to no other triangle",
                    "close the hole at this edge (or, if a neighbouring triangle has this edge with the same "
                    "direction, reverse the orientation of that triangle)");
    const double length = (vertex(edge.second) - vertex(edge.first)).norm();
    if (edge.first < edge.second && length < kMinRelativeEdge * size)
      throw failure(name_ + ": edge " + edge_text + " of triangle " + std::to_string(ts[0]) + " has length " +
                        number_text(length) + ", below " + number_text(kMinRelativeEdge) +
                        " × the bounding-box size " + number_text(size),
                    "merge the two nearly coincident vertices (collapse the edge)");
  }
  for (Index v = 0; v < n; ++v) {
    const auto& a = around[static_cast<std::size_t>(v)];
    if (a.empty())
      throw failure(
          name_ + ": vertex " + std::to_string(v) + " " + point_text(vertex(v)) + " belongs to no triangle",
          "remove unused vertices");
    if (!single_fan(v, a, triangles_))
      throw failure(name_ + " is not 2-manifold at vertex " + std::to_string(v) + " " +
                        point_text(vertex(v)) + ": its triangles form more than one fan",
                    "split the vertex into one vertex per fan, or remesh there");
  }

  // Geometry with exact predicates.
  for (Index t = 0; t < m; ++t) {
    const Triangle& tr = triangle(t);
    if (CGAL::collinear(to_cgal(vertex(tr[0])), to_cgal(vertex(tr[1])), to_cgal(vertex(tr[2]))))
      throw failure(name_ + ": triangle " + std::to_string(t) + " " + triangle_text(tr) +
                        " is degenerate (its vertices are collinear)",
                    "move a vertex off the line or remove the triangle by collapsing its shortest edge");
  }
  Mesh mesh;
  {
    std::vector<KPoint> points;
    points.reserve(static_cast<std::size_t>(n));
    for (const auto& p : vertices_) points.push_back(to_cgal(p));
    std::vector<std::vector<std::size_t>> polygons;
    polygons.reserve(static_cast<std::size_t>(m));
    for (const auto& tr : triangles_)
      polygons.push_back({static_cast<std::size_t>(tr[0]), static_cast<std::size_t>(tr[1]),
                          static_cast<std::size_t>(tr[2])});
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  }
  if (static_cast<Index>(mesh.number_of_faces()) != m)
    throw failure(name_ + ": CGAL could not build a surface mesh from the triangles", "remesh the surface");
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> crossing;
  PMP::self_intersections(faces(mesh), mesh, std::back_inserter(crossing));
  if (!crossing.empty()) {
    // Faces are created in the order of the triangle list, so descriptors are triangle indices.
    const Index a = static_cast<Index>(crossing.front().first),
                b = static_cast<Index>(crossing.front().second);
    throw failure(name_ + " intersects itself: triangle " + std::to_string(std::min(a, b)) + " " +
                      triangle_text(triangle(std::min(a, b))) + " and triangle " +
                      std::to_string(std::max(a, b)) + " " + triangle_text(triangle(std::max(a, b))) +
                      " intersect (" + std::to_string(crossing.size()) + " intersecting pairs in all)",
                  "move the vertices so that triangles meet only along shared edges and vertices");
  }
  const auto component = mesh.add_property_map<Mesh::Face_index, std::size_t>("f:component", 0).first;
  const std::size_t components = PMP::connected_components(mesh, component);
  if (components != 1)
    throw failure(name_ + " has " + std::to_string(components) + " separate surface pieces",
                  "give one connected closed surface (one polyhedron per cage)");
  if (!PMP::is_outward_oriented(mesh))
    throw failure(name_ + " is oriented inward (signed volume " + number_text(signed_volume()) + ")",
                  "reverse the orientation (swap two vertex indices in every triangle)");
}

Real Polyhedron::signed_volume() const {
  Real v = 0;
  for (const auto& t : triangles_) v += vertex(t[0]).dot(vertex(t[1]).cross(vertex(t[2])));
  return v / 6;
}

Real Polyhedron::surface_area() const {
  Real a = 0;
  for (const auto& t : triangles_)
    a += (vertex(t[1]) - vertex(t[0])).cross(vertex(t[2]) - vertex(t[0])).norm();
  return a / 2;
}

Point<3> Polyhedron::bbox_min() const {
  Point<3> m = vertices_.front();
  for (const auto& v : vertices_) m = m.cwiseMin(v);
  return m;
}

Point<3> Polyhedron::bbox_max() const {
  Point<3> m = vertices_.front();
  for (const auto& v : vertices_) m = m.cwiseMax(v);
  return m;
}

Polyhedron Polyhedron::reversed() const {
  std::vector<Triangle> t = triangles_;
  for (auto& tr : t) std::swap(tr[1], tr[2]);
  Polyhedron r(vertices_, std::move(t), name_);
  r.triangle_parts_ = triangle_parts_;
  return r;
}

void require_same_triangulation(const Polyhedron& source, const Polyhedron& target) {
  if (source.vertex_count() != target.vertex_count())
    throw failure(source.name() + " has " + std::to_string(source.vertex_count()) + " vertices but " +
                      target.name() + " has " + std::to_string(target.vertex_count()),
                  "give both polyhedra the same vertices in the same order (vertex i moves to vertex i)");
  if (source.triangle_count() != target.triangle_count())
    throw failure(source.name() + " has " + std::to_string(source.triangle_count()) + " triangles but " +
                      target.name() + " has " + std::to_string(target.triangle_count()),
                  "give both polyhedra the same triangle list");
  for (Index t = 0; t < source.triangle_count(); ++t)
    if (source.triangle(t) != target.triangle(t))
      throw failure("triangle " + std::to_string(t) + " is " + triangle_text(source.triangle(t)) + " in " +
                        source.name() + " but " + triangle_text(target.triangle(t)) + " in " + target.name(),
                    "give both polyhedra the same triangle list");
}

Real winding_number(const Polyhedron& P, const Point<3>& x) {
  Real omega = 0;
  for (const auto& t : P.triangles()) {
    const Point<3> a = P.vertex(t[0]) - x, b = P.vertex(t[1]) - x, c = P.vertex(t[2]) - x;
    const Real la = a.norm(), lb = b.norm(), lc = c.norm();
    omega += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return omega / (4 * std::numbers::pi);
}

}  // namespace warpfem
