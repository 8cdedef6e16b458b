#include "core/mesh/polygon_mesher.hpp"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <unordered_map>

#include "core/error.hpp"

namespace warpfem {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Delaunay_mesh_vertex_base_2<Kernel>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
using Mesher = CGAL::Delaunay_mesher_2<Cdt, Criteria>;
constexpr std::size_t kSequentialInsertionLimit = 2048;
// The polygon's edges in an AABB tree: a boundary facet finds the edge it lies
// on in logarithmic time (a scan over all edges made meshing quadratic in the
// number of polygon vertices). CGAL 5.5's AABB tree is 3D: the edges lie in z = 0.
using Segments = std::vector<Kernel::Segment_3>;
using EdgePrimitive = CGAL::AABB_segment_primitive<Kernel, Segments::const_iterator>;
using EdgeTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, EdgePrimitive>>;

/// The corners, and with max_length > 0 the points splitting every edge into
/// ceil(length / max_length) equal pieces, in boundary order.
std::vector<Point<2>> boundary_nodes(const Polygon& polygon, double max_length) {
  std::vector<Point<2>> nodes;
  for (Index i = 0; i < polygon.size(); ++i) {
    const Point<2> a = polygon.vertex(i), b = polygon.vertex(i + 1);
    const Index pieces =
        max_length > 0 ? std::max<Index>(1, static_cast<Index>(std::ceil((b - a).norm() / max_length - 1e-9)))
                       : 1;
    for (Index j = 0; j < pieces; ++j) {
      const double t = static_cast<double>(j) / static_cast<double>(pieces);
      nodes.push_back((1 - t) * a + t * b);
    }
  }
  return nodes;
}
}  // namespace

Mesh<2> mesh_polygon(const Polygon& polygon, const PolygonMeshOptions& options,
                     const std::vector<Point<2>>& interior_points) {
  // CGAL compares squared lengths: a bound whose square underflows to 0 would mean "no bound".
  const double h = options.max_edge_length;
  if (h > 0 && !(h * h > 0 && std::isfinite(h))) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", h);
    throw Error(
        std::string("edge length bound ") + text + " cannot be used: its square is not a positive double",
        {.file = "", .key_path = "mesh.max_edge_length", .hint = "choose a larger edge length"});
  }
  const Index n = polygon.size();
  Cdt cdt;
  std::vector<Cdt::Point> nodes;
  for (const Point<2>& p : boundary_nodes(polygon, options.max_boundary_edge_length))
    nodes.emplace_back(p.x(), p.y());
  if (nodes.size() > kSequentialInsertionLimit) {
    // All nodes and edges at once: CGAL sorts them spatially first. In
    // boundary order, nearly co-circular nodes (any finely sampled smooth
    // outline) each flip O(n) triangles: quadratic in the node count.
    std::vector<std::pair<std::size_t, std::size_t>> segments;
    segments.reserve(nodes.size());
    for (std::size_t j = 0; j < nodes.size(); ++j) segments.emplace_back(j, (j + 1) % nodes.size());
    cdt.insert_constraints(nodes.begin(), nodes.end(), segments.begin(), segments.end());
  } else {
    // Few nodes: boundary order, which fixes the triangulation's tie-breaks
    // (and so the refined mesh) independently of CGAL's spatial sort.
    std::vector<Cdt::Vertex_handle> handles;
    for (const Cdt::Point& p : nodes) handles.push_back(cdt.insert(p));
    for (std::size_t j = 0; j < handles.size(); ++j)
      cdt.insert_constraint(handles[j], handles[(j + 1) % handles.size()]);
  }
  for (const Point<2>& p : interior_points) cdt.insert(Cdt::Point(p.x(), p.y()));

  // A seed-free refinement meshes every bounded component; the polygon is
  // simple so the only bounded component is its interior.
  Mesher mesher(cdt);
  const double size = options.max_edge_length > 0 ? options.max_edge_length : 0.0;
  mesher.set_criteria(Criteria(options.shape_bound, size));
  mesher.refine_mesh();

  Mesh<2> mesh;
  mesh.cell_type = CellType::triangle;
  std::unordered_map<Cdt::Vertex_handle, Index> index;
  std::vector<Point<2>> verts;
  std::vector<std::array<Index, 3>> tris;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    std::array<Index, 3> t{};
    for (int k = 0; k < 3; ++k) {
      auto v = f->vertex(k);
      auto [it, inserted] = index.try_emplace(v, static_cast<Index>(verts.size()));
      if (inserted) verts.emplace_back(v->point().x(), v->point().y());
      t[k] = it->second;
    }
    tris.push_back(t);  // CGAL faces are counter-clockwise
  }
  if (tris.empty())
    throw Error(
        polygon.name() + ": meshing produced no triangles",
        {.file = "", .key_path = "", .hint = "check the polygon (it must be simple and counter-clockwise)"});

  mesh.vertices.resize(static_cast<Index>(verts.size()), 2);
  for (std::size_t i = 0; i < verts.size(); ++i)
    mesh.vertices.row(static_cast<Index>(i)) = verts[i].transpose();
  mesh.cells.resize(static_cast<Index>(tris.size()), 3);
  for (std::size_t c = 0; c < tris.size(); ++c)
    for (int k = 0; k < 3; ++k) mesh.cells(static_cast<Index>(c), k) = tris[c][k];

  // Boundary facets: edges of in-domain faces whose neighbour is outside.
  Segments edges;
  edges.reserve(static_cast<std::size_t>(n));
  for (Index e = 0; e < n; ++e) {
    const Point<2> a = polygon.vertex(e), b = polygon.vertex(e + 1);
    edges.emplace_back(Kernel::Point_3(a.x(), a.y(), 0), Kernel::Point_3(b.x(), b.y(), 0));
  }
  EdgeTree tree(edges.cbegin(), edges.cend());
  tree.accelerate_distance_queries();
  std::vector<std::array<Index, 2>> facets;
  std::vector<int> tags;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    for (int k = 0; k < 3; ++k) {
      auto nb = f->neighbor(k);
      if (!cdt.is_infinite(nb) && nb->is_in_domain()) continue;
      // Edge opposite vertex k, oriented counter-clockwise around the domain.
      const Index a = index.at(f->vertex(cdt.ccw(k)));
      const Index b = index.at(f->vertex(cdt.cw(k)));
      const Point<2> mid = 0.5 * (verts[a] + verts[b]);
      const auto nearest = tree.closest_point_and_primitive(Kernel::Point_3(mid.x(), mid.y(), 0));
      facets.push_back({a, b});
      tags.push_back(static_cast<int>(std::distance(edges.cbegin(), nearest.second)));
    }
  }
  mesh.boundary_facets.resize(static_cast<Index>(facets.size()), 2);
  for (std::size_t i = 0; i < facets.size(); ++i) {
    mesh.boundary_facets(static_cast<Index>(i), 0) = facets[i][0];
    mesh.boundary_facets(static_cast<Index>(i), 1) = facets[i][1];
  }
  mesh.facet_tags = std::move(tags);
  return mesh;
}

}  // namespace warpfem
