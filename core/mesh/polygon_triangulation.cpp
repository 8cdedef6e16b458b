#include "core/mesh/polygon_triangulation.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <map>

namespace warpfem {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;
}  // namespace

std::vector<std::array<int, 3>> triangulate_simple_polygon(const std::vector<Point<2>>& vertices) {
  std::vector<Kernel::Point_2> ring;
  ring.reserve(vertices.size());
  for (const auto& v : vertices) ring.emplace_back(v(0), v(1));
  if (ring.size() < 3 || !CGAL::is_simple_2(ring.begin(), ring.end(), Kernel()) ||
      CGAL::orientation_2(ring.begin(), ring.end(), Kernel()) != CGAL::COUNTERCLOCKWISE)
    return {};
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handles;
  handles.reserve(ring.size());
  for (std::size_t i = 0; i < ring.size(); ++i) {
    handles.push_back(cdt.insert(ring[i]));
    handles.back()->info() = static_cast<int>(i);
  }
  for (std::size_t i = 0; i < ring.size(); ++i)
    cdt.insert_constraint(handles[i], handles[(i + 1) % ring.size()]);
  // A simple polygon's inside is the faces reached from the infinite face
  // across an odd number of constrained edges: flood fill by parity.
  std::vector<std::array<int, 3>> triangles;
  std::vector<Cdt::Face_handle> stack{cdt.infinite_face()};
  std::map<Cdt::Face_handle, bool> inside{{cdt.infinite_face(), false}};
  while (!stack.empty()) {
    const Cdt::Face_handle f = stack.back();
    stack.pop_back();
    for (int e = 0; e < 3; ++e) {
      const Cdt::Face_handle n = f->neighbor(e);
      if (inside.count(n)) continue;
      const bool in = inside[f] != cdt.is_constrained({f, e});
      inside[n] = in;
      stack.push_back(n);
    }
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (inside[f]) triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  return triangles;
}

}  // namespace warpfem
