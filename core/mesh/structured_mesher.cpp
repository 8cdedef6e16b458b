#include "core/mesh/structured_mesher.hpp"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include "core/error.hpp"
#include "core/mesh/boundary_locator.hpp"
#include "core/mesh/edge_numbering.hpp"

namespace warpfem {

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
      throw Error("boundary facet " + std::to_string(f) + " of the mesh does not lie on the polygon " +
                      polygon.name(),
                  {.file = "", .key_path = "mesh", .hint = "the mesh must cover exactly the source polygon"});
    mesh.facet_tags[f] = e;
  }
}

Mesh<2> structured_mesh(const Polygon& rectangle, int nx, int ny, CellType type) {
  if (!is_axis_aligned_rectangle(rectangle))
    throw Error("a structured mesh needs an axis-aligned rectangular source polygon; " + rectangle.name() +
                    " is not one",
                {.file = "",
                 .key_path = "mesh.type",
                 .hint = "use \"delaunay\" or \"quad_split\" for general polygons"});
  if (nx < 1 || ny < 1)
    throw Error("structured mesh needs at least one cell per direction",
                {.file = "", .key_path = "mesh.cells", .hint = "give [nx, ny] >= [1, 1]"});
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

IndexTable find_boundary_facets(const Mesh<3>& mesh) {
  mesh.require_whole("find_boundary_facets");
  const auto& faces = cell_faces(mesh.cell_type);
  const int nf = static_cast<int>(faces.size()), nvf = static_cast<int>(faces[0].size());
  // Sort the facets by their sorted vertex ids: a facet met once is on the boundary.
  const Index n = mesh.num_cells() * nf;
  std::vector<std::array<TableIndex, 4>> keys(static_cast<std::size_t>(n), {-1, -1, -1, -1});
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (int f = 0; f < nf; ++f) {
      auto& key = keys[static_cast<std::size_t>(c * nf + f)];
      for (int k = 0; k < nvf; ++k) key[k] = mesh.cells(c, faces[f][k]);
      std::sort(key.begin(), key.begin() + nvf);
    }
  std::vector<Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Index{0});
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return keys[a] < keys[b]; });
  std::vector<Index> boundary;  // cell * nf + local facet
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i + 1;
    while (j < order.size() && keys[order[j]] == keys[order[i]]) ++j;
    if (j - i > 2)
      throw Error(
          "the mesh is not conforming: a facet is shared by " + std::to_string(j - i) + " cells",
          {.file = "", .key_path = "mesh", .hint = "every interior facet must belong to exactly two cells"});
    if (j - i == 1) boundary.push_back(order[i]);
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  IndexTable out(static_cast<Index>(boundary.size()), nvf);
  for (std::size_t b = 0; b < boundary.size(); ++b)
    for (int k = 0; k < nvf; ++k)
      out(static_cast<Index>(b), k) = mesh.cells(boundary[b] / nf, faces[boundary[b] % nf][k]);
  return out;
}

namespace {
// Kuhn/Freudenthal split of the unit cube: one tetrahedron per ordering of
// the axes, along the path 000 -> e_a -> e_a + e_b -> 111. Corners are
// numbered by bits (x = 1, y = 2, z = 4); odd orderings are reflected, so two
// vertices are swapped to keep every tetrahedron positively oriented.
std::array<std::array<int, 4>, 6> kuhn_tetrahedra() {
  std::array<std::array<int, 4>, 6> tets{};
  std::array<int, 3> axes{0, 1, 2};
  int t = 0;
  do {
    std::array<int, 4> tet{0, 1 << axes[0], (1 << axes[0]) | (1 << axes[1]), 7};
    const bool even = (axes[0] + 1) % 3 == axes[1];  // cyclic orderings are even
    if (!even) std::swap(tet[2], tet[3]);
    tets[t++] = tet;
  } while (std::next_permutation(axes.begin(), axes.end()));
  return tets;
}
}  // namespace

Mesh<3> structured_box_mesh(const Point<3>& lo, const Point<3>& hi, const std::array<int, 3>& n,
                            CellType type) {
  if (n[0] < 1 || n[1] < 1 || n[2] < 1)
    throw Error("a structured box mesh needs at least one cell per direction",
                {.file = "", .key_path = "mesh.cells", .hint = "give [nx, ny, nz] >= [1, 1, 1]"});
  if (!(hi.array() > lo.array()).all())
    throw Error(
        "a structured box mesh needs a box with hi > lo in every coordinate",
        {.file = "", .key_path = "mesh", .hint = "give the lower corner first and a positive extent"});
  if (type != CellType::tetrahedron && type != CellType::hexahedron)
    throw Error("a structured box mesh is made of tetrahedra or hexahedra, not " + to_string(type) + " cells",
                {.file = "", .key_path = "mesh.cell_type", .hint = "use tetrahedron or hexahedron"});
  const Index nx = n[0], ny = n[1], nz = n[2];
  const Index num_vertices = (nx + 1) * (ny + 1) * (nz + 1);
  const Index num_boxes = nx * ny * nz;
  Mesh<3> m;
  m.cell_type = type;
  m.vertices.resize(checked_table_size(num_vertices, "structured_box_mesh vertices"), 3);
  auto vid = [&](Index i, Index j, Index k) {
    return static_cast<TableIndex>((k * (ny + 1) + j) * (nx + 1) + i);
  };
  for (Index k = 0; k <= nz; ++k)
    for (Index j = 0; j <= ny; ++j)
      for (Index i = 0; i <= nx; ++i) {
        const Index idx[3] = {i, j, k};
        for (int d = 0; d < 3; ++d)
          // Exact ends, so boundary vertices lie exactly on the box faces.
          m.vertices(vid(i, j, k), d) = idx[d] == n[d] ? hi(d) : lo(d) + (hi(d) - lo(d)) * idx[d] / n[d];
      }
  // Corner c (bits x = 1, y = 2, z = 4) of box (i, j, k).
  auto corner = [&](Index i, Index j, Index k, int c) {
    return vid(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
  };
  if (type == CellType::hexahedron) {
    static const int hex_corners[8] = {0, 1, 3, 2, 4, 5, 7, 6};  // VTK hexahedron order
    m.cells.resize(checked_table_size(num_boxes, "structured_box_mesh cells"), 8);
    for (Index k = 0; k < nz; ++k)
      for (Index j = 0; j < ny; ++j)
        for (Index i = 0; i < nx; ++i)
          for (int v = 0; v < 8; ++v) m.cells((k * ny + j) * nx + i, v) = corner(i, j, k, hex_corners[v]);
  } else {
    const auto tets = kuhn_tetrahedra();
    m.cells.resize(checked_table_size(6 * num_boxes, "structured_box_mesh cells"), 4);
    for (Index k = 0; k < nz; ++k)
      for (Index j = 0; j < ny; ++j)
        for (Index i = 0; i < nx; ++i)
          for (int t = 0; t < 6; ++t)
            for (int v = 0; v < 4; ++v)
              m.cells(6 * ((k * ny + j) * nx + i) + t, v) = corner(i, j, k, tets[t][v]);
  }
  m.boundary_facets = find_boundary_facets(m);
  // Tag: the box face all vertices of the facet lie on (exact coordinates).
  m.facet_tags.resize(static_cast<std::size_t>(m.num_boundary_facets()));
  for (Index f = 0; f < m.num_boundary_facets(); ++f) {
    int tag = -1;
    for (int face = 0; face < 6 && tag < 0; ++face) {
      const int d = face / 2;
      const double plane = face % 2 == 0 ? lo(d) : hi(d);
      bool on = true;
      for (Index k = 0; k < m.boundary_facets.cols(); ++k)
        on = on && m.vertices(m.boundary_facets(f, k), d) == plane;
      if (on) tag = face;
    }
    require(tag >= 0, "structured_box_mesh: boundary facet off the box faces");
    m.facet_tags[static_cast<std::size_t>(f)] = tag;
  }
  return m;
}

}  // namespace warpfem
