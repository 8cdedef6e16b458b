#include "mapping/harmonic/triangle_mesh.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <map>
#include <unordered_map>

#include "core/error.hpp"

namespace warpfem::mapping {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<CDT>;

void fill_neighbors(TriangleMesh& m) {
  std::map<std::pair<Index, Index>, std::pair<Index, int>> edges;  // (min, max) -> (triangle, local)
  m.neighbors.assign(m.triangles.size(), {-1, -1, -1});
  for (Index t = 0; t < m.num_triangles(); ++t)
    for (int i = 0; i < 3; ++i) {
      Index a = m.triangles[static_cast<std::size_t>(t)][(i + 1) % 3];
      Index b = m.triangles[static_cast<std::size_t>(t)][(i + 2) % 3];
      if (a > b) std::swap(a, b);
      auto [it, fresh] = edges.try_emplace({a, b}, t, i);
      if (!fresh) {
        m.neighbors[static_cast<std::size_t>(t)][i] = it->second.first;
        m.neighbors[static_cast<std::size_t>(it->second.first)][it->second.second] = t;
      }
    }
}

}  // namespace

TriangleMesh mesh_polygon(const Polygon& domain, Real max_edge_length, Index max_triangles) {
  require(max_edge_length > 0, "harmonic map: the mesh edge length must be positive");
  const Real area = domain.signed_area();
  const Real estimate = 4 * area / (0.43 * max_edge_length * max_edge_length);
  if (estimate > static_cast<Real>(max_triangles))
    throw Error("harmonic map: a mesh of " + domain.name() + " with edges ≤ " +
                    std::to_string(max_edge_length) + " would have about " +
                    std::to_string(static_cast<long long>(estimate)) + " triangles",
                {.file = "", .key_path = "map.fem_max_edge_length", .hint = "choose a larger edge length"});

  const BoundaryNodes nodes = subdivide_boundary(domain, max_edge_length);
  CDT cdt;
  std::vector<CDT::Vertex_handle> handles;
  for (const Point<2>& p : nodes.x) handles.push_back(cdt.insert(K::Point_2(p.x(), p.y())));
  for (std::size_t j = 0; j < handles.size(); ++j)
    cdt.insert_constraint(handles[j], handles[(j + 1) % handles.size()]);
  CGAL::refine_Delaunay_mesh_2(cdt, Criteria(0.125, max_edge_length));

  TriangleMesh m;
  std::unordered_map<CDT::Vertex_handle, Index> index;
  std::vector<Point<2>> verts;
  auto id = [&](CDT::Vertex_handle v) {
    auto [it, fresh] = index.try_emplace(v, static_cast<Index>(verts.size()));
    if (fresh) verts.emplace_back(v->point().x(), v->point().y());
    return it->second;
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    m.triangles.push_back({id(f->vertex(0)), id(f->vertex(1)), id(f->vertex(2))});
  }
  m.vertices.resize(static_cast<Index>(verts.size()), 2);
  for (std::size_t v = 0; v < verts.size(); ++v) m.vertices.row(static_cast<Index>(v)) = verts[v].transpose();

  // boundary vertices: ends of constrained edges; their (edge, t) by projection
  m.on_boundary.assign(verts.size(), false);
  m.at.assign(verts.size(), BoundaryPoint{});
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e) {
    if (!cdt.is_constrained(*e)) continue;
    for (int k = 1; k <= 2; ++k) {
      auto it = index.find(e->first->vertex((e->second + k) % 3));
      if (it != index.end()) m.on_boundary[static_cast<std::size_t>(it->second)] = true;
    }
  }
  for (std::size_t v = 0; v < verts.size(); ++v)
    if (m.on_boundary[v]) m.at[v] = closest_boundary_point(domain, verts[v], nullptr);
  fill_neighbors(m);
  return m;
}

}  // namespace warpfem::mapping
