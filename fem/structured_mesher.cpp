#include "fem/structured_mesher.hpp"

#include <unordered_map>

#include "core/error.hpp"
#include "fem/boundary_locator.hpp"
#include "fem/edge_numbering.hpp"

namespace warpfem::fem {

bool is_axis_aligned_rectangle(const Polygon& polygon) {
  const Point<2> lo = polygon.bbox_min(), hi = polygon.bbox_max();
  const double tol = 1e-12 * (hi - lo).norm();
  for (const auto& v : polygon.vertices()) {
    const bool on_side = std::abs(v.x() - lo.x()) <= tol || std::abs(v.x() - hi.x()) <= tol ||
                         std::abs(v.y() - lo.y()) <= tol || std::abs(v.y() - hi.y()) <= tol;
    if (!on_side) return false;
  }
  const double box = (hi - lo).prod();
  return std::abs(polygon.signed_area() - box) <= 1e-12 * box;
}

IndexTable find_boundary_facets(const Mesh<2>& mesh) {
  const EdgeNumbering edges(mesh);
  std::vector<int> count(static_cast<std::size_t>(edges.num_edges()), 0);
  const auto& local = cell_edges(mesh.cell_type);
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (std::size_t e = 0; e < local.size(); ++e) ++count[edges.cell_edge(c, static_cast<int>(e))];
  std::vector<std::array<Index, 2>> facets;
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (std::size_t e = 0; e < local.size(); ++e)
      if (count[edges.cell_edge(c, static_cast<int>(e))] == 1)
        facets.push_back({mesh.cells(c, local[e][0]), mesh.cells(c, local[e][1])});  // cells are CCW
  IndexTable out(static_cast<Index>(facets.size()), 2);
  for (std::size_t f = 0; f < facets.size(); ++f)
    out.row(static_cast<Index>(f)) << facets[f][0], facets[f][1];
  return out;
}

void tag_boundary_facets(Mesh<2>& mesh, const Polygon& polygon) {
  const BoundaryLocator locator(polygon);
  mesh.facet_tags.resize(static_cast<std::size_t>(mesh.num_boundary_facets()));
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f) {
    const Point<2> mid =
        0.5 * (mesh.vertex(mesh.boundary_facets(f, 0)) + mesh.vertex(mesh.boundary_facets(f, 1)));
    const int e = locator.edge_at(mid);
    if (e < 0)
      throw Error(
          "boundary facet " + std::to_string(f) + " of the mesh does not lie on the polygon " +
              polygon.name(),
          {.file = "", .key_path = "/mesh", .hint = "the mesh must cover exactly the source polygon"});
    mesh.facet_tags[f] = e;
  }
}

Mesh<2> structured_mesh(const Polygon& rectangle, int nx, int ny, CellType type) {
  if (!is_axis_aligned_rectangle(rectangle))
    throw Error("a structured mesh needs an axis-aligned rectangular source polygon; " + rectangle.name() +
                    " is not one",
                {.file = "",
                 .key_path = "/mesh/type",
                 .hint = "use \"delaunay\" or \"quad_split\" for general polygons"});
  if (nx < 1 || ny < 1)
    throw Error("structured mesh needs at least one cell per direction",
                {.file = "", .key_path = "/mesh/cells", .hint = "give [nx, ny] >= [1, 1]"});
  require(type == CellType::triangle || type == CellType::quadrilateral, "structured_mesh: 2D cells only");
  const Point<2> lo = rectangle.bbox_min(), hi = rectangle.bbox_max();
  Mesh<2> m;
  m.cell_type = type;
  m.vertices.resize(static_cast<Index>(nx + 1) * (ny + 1), 2);
  auto vid = [nx](int i, int j) { return static_cast<Index>(j) * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.vertices.row(vid(i, j)) << lo.x() + (hi.x() - lo.x()) * i / nx, lo.y() + (hi.y() - lo.y()) * j / ny;
  // Exact corners, so boundary vertices lie exactly on the polygon.
  for (int j = 0; j <= ny; ++j) m.vertices(vid(nx, j), 0) = hi.x();
  for (int i = 0; i <= nx; ++i) m.vertices(vid(i, ny), 1) = hi.y();
  if (type == CellType::quadrilateral) {
    m.cells.resize(static_cast<Index>(nx) * ny, 4);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.cells.row(static_cast<Index>(j) * nx + i) << vid(i, j), vid(i + 1, j), vid(i + 1, j + 1),
            vid(i, j + 1);
  } else {
    m.cells.resize(2 * static_cast<Index>(nx) * ny, 3);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Index c = 2 * (static_cast<Index>(j) * nx + i);
        m.cells.row(c) << vid(i, j), vid(i + 1, j), vid(i + 1, j + 1);
        m.cells.row(c + 1) << vid(i, j), vid(i + 1, j + 1), vid(i, j + 1);
      }
  }
  m.boundary_facets = find_boundary_facets(m);
  tag_boundary_facets(m, rectangle);
  return m;
}

Mesh<2> split_into_quadrilaterals(const Mesh<2>& tri) {
  require(tri.cell_type == CellType::triangle, "split_into_quadrilaterals: needs a triangle mesh");
  const EdgeNumbering edges(tri);
  const Index nv = tri.num_vertices(), ne = edges.num_edges(), nc = tri.num_cells();
  Mesh<2> q;
  q.cell_type = CellType::quadrilateral;
  q.vertices.resize(nv + ne + nc, 2);
  q.vertices.topRows(nv) = tri.vertices;
  for (Index e = 0; e < ne; ++e)
    q.vertices.row(nv + e) =
        0.5 * (tri.vertices.row(edges.vertices(e)[0]) + tri.vertices.row(edges.vertices(e)[1]));
  q.cells.resize(3 * nc, 4);
  for (Index c = 0; c < nc; ++c) {
    const Index v0 = tri.cells(c, 0), v1 = tri.cells(c, 1), v2 = tri.cells(c, 2);
    const Index m01 = nv + edges.cell_edge(c, 0), m12 = nv + edges.cell_edge(c, 1),
                m20 = nv + edges.cell_edge(c, 2);
    const Index centre = nv + ne + c;
    q.vertices.row(centre) = (tri.vertices.row(v0) + tri.vertices.row(v1) + tri.vertices.row(v2)) / 3.0;
    q.cells.row(3 * c) << v0, m01, centre, m20;
    q.cells.row(3 * c + 1) << v1, m12, centre, m01;
    q.cells.row(3 * c + 2) << v2, m20, centre, m12;
  }
  q.boundary_facets.resize(2 * tri.num_boundary_facets(), 2);
  q.facet_tags.resize(static_cast<std::size_t>(2 * tri.num_boundary_facets()));
  for (Index f = 0; f < tri.num_boundary_facets(); ++f) {
    const Index a = tri.boundary_facets(f, 0), b = tri.boundary_facets(f, 1);
    const Index m = nv + edges.find(a, b);
    q.boundary_facets.row(2 * f) << a, m;
    q.boundary_facets.row(2 * f + 1) << m, b;
    q.facet_tags[2 * f] = q.facet_tags[2 * f + 1] = tri.facet_tags[f];
  }
  return q;
}

}  // namespace warpfem::fem
