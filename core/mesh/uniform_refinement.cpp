#include "core/mesh/uniform_refinement.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/edge_numbering.hpp"
#include "core/prefault.hpp"

namespace warpfem {

namespace {

// ---- The tables ------------------------------------------------------------

/// A reference cell in doubled integer coordinates (vertices at 0 or 2, so
/// every refinement node has integer coordinates), with the edges and faces of
/// reference_cell.hpp (checked against cell_edges / cell_faces on first use).
struct DoubledCell {
  int vertices, edges, faces, centres;
  std::array<std::array<int, 3>, 8> vertex;
  std::array<std::array<int, 2>, 12> edge;
  std::array<std::array<int, 4>, 6> face;
};

constexpr DoubledCell kTriangle{3, 3, 0, 0, {{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}}, {{{0, 1}, {1, 2}, {2, 0}}},
                                {}};
constexpr DoubledCell kQuadrilateral{
    4, 4, 0, 1, {{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}}}, {{{0, 1}, {1, 2}, {2, 3}, {3, 0}}}, {}};
constexpr DoubledCell kTetrahedron{4,
                                   6,
                                   0,
                                   0,
                                   {{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}}},
                                   {{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}},
                                   {}};
constexpr DoubledCell kHexahedron{
    8,
    12,
    6,
    1,
    {{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}}},
    {{{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}},
    {{{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}}}};

/// Doubled position of every local node: vertices, edge midpoints, face centres, centre.
constexpr std::array<std::array<int, 3>, RefinementTable::kMaxNodes> node_positions(const DoubledCell& c) {
  std::array<std::array<int, 3>, RefinementTable::kMaxNodes> p{};
  int n = 0;
  for (int v = 0; v < c.vertices; ++v) p[n++] = c.vertex[v];
  for (int e = 0; e < c.edges; ++e)
    for (int d = 0; d < 3; ++d) p[n + e][d] = (c.vertex[c.edge[e][0]][d] + c.vertex[c.edge[e][1]][d]) / 2;
  n += c.edges;
  for (int f = 0; f < c.faces; ++f, ++n)
    for (int d = 0; d < 3; ++d) {
      int s = 0;
      for (int k = 0; k < 4; ++k) s += c.vertex[c.face[f][k]][d];
      p[n][d] = s / 4;
    }
  for (int k = 0; k < c.centres; ++k, ++n)
    for (int d = 0; d < 3; ++d) {
      int s = 0;
      for (int v = 0; v < c.vertices; ++v) s += c.vertex[v][d];
      p[n][d] = s / c.vertices;
    }
  return p;
}

/// The refinement of `cell`: child k < vertices at vertex k (its vertex j at
/// the midpoint of parent vertices k and j), then the `interior` children.
template <std::size_t interior_children>
constexpr RefinementTable make_table(const DoubledCell& cell,
                                     const std::array<std::array<int, 4>, interior_children>& interior) {
  RefinementTable t;
  t.vertices = cell.vertices, t.edges = cell.edges, t.faces = cell.faces, t.centres = cell.centres;
  t.children = cell.vertices + static_cast<int>(interior_children);
  const auto pos = node_positions(cell);
  for (int k = 0; k < cell.vertices; ++k)
    for (int j = 0; j < cell.vertices; ++j) {
      std::array<int, 3> x{};
      for (int d = 0; d < 3; ++d) x[d] = (cell.vertex[k][d] + cell.vertex[j][d]) / 2;
      int node = -1;
      for (int n = 0; n < t.nodes(); ++n)
        if (pos[n] == x) node = n;
      t.child_nodes[k][j] = node;
    }
  for (std::size_t i = 0; i < interior_children; ++i)
    for (int j = 0; j < cell.vertices; ++j) t.child_nodes[cell.vertices + i][j] = interior[i][j];
  return t;
}

// Triangle: the middle child (m01, m12, m20). Tetrahedron (local nodes m01 = 4,
// m12 = 5, m20 = 6, m03 = 7, m13 = 8, m23 = 9): Bey's interior children
// (m01, m02, m03, m13), (m01, m02, m12, m13), (m02, m03, m13, m23),
// (m02, m12, m13, m23), the second and fourth with vertices 0 and 2 swapped
// to orient them positively (see the header).
constexpr RefinementTable kTriangleTable = make_table<1>(kTriangle, {{{3, 4, 5, 0}}});
constexpr RefinementTable kQuadrilateralTable = make_table<0>(kQuadrilateral, {});
constexpr RefinementTable kTetrahedronTable =
    make_table<4>(kTetrahedron, {{{4, 6, 7, 8}, {5, 6, 4, 8}, {6, 7, 8, 9}, {8, 5, 6, 9}}});
constexpr RefinementTable kHexahedronTable = make_table<0>(kHexahedron, {});

const DoubledCell& doubled_cell(CellType type) {
  switch (type) {
    case CellType::triangle: return kTriangle;
    case CellType::quadrilateral: return kQuadrilateral;
    case CellType::tetrahedron: return kTetrahedron;
    case CellType::hexahedron: return kHexahedron;
  }
  throw Error("refinement_table: unknown cell type");
}

/// The local nodes in the order the children first use them: the order in
/// which one cell's children number their fine vertices.
struct FirstUse {
  std::array<int, RefinementTable::kMaxNodes> node{};
  int count = 0;
};
constexpr FirstUse first_use(const RefinementTable& t) {
  FirstUse u;
  std::array<bool, RefinementTable::kMaxNodes> seen{};
  for (int k = 0; k < t.children; ++k)
    for (int j = 0; j < t.vertices; ++j) {
      const int n = t.child_nodes[k][j];
      if (!seen[n]) seen[n] = true, u.node[u.count++] = n;
    }
  return u;
}

// ---- Faces of hexahedral meshes --------------------------------------------

/// Global numbering of the quadrilateral faces of a hexahedral mesh, in the
/// order the cells first use them, and a lookup from a face's vertices.
class QuadFaces {
 public:
  explicit QuadFaces(const Mesh<3>& mesh) : cell_face_(mesh.num_cells(), 6) {
    const auto& local = cell_faces(CellType::hexahedron);
    const Index nc = mesh.num_cells();
    std::vector<std::pair<Key, Index>> slots;  // (sorted vertices, 6 c + local face)
    slots.reserve(static_cast<std::size_t>(6 * nc));
    for (Index c = 0; c < nc; ++c)
      for (int f = 0; f < 6; ++f) {
        Key k;
        for (int j = 0; j < 4; ++j) k[static_cast<std::size_t>(j)] = mesh.cells(c, local[f][j]);
        std::sort(k.begin(), k.end());
        slots.push_back({k, 6 * c + f});
      }
    std::sort(slots.begin(), slots.end());
    // Groups of equal keys; a group's first slot is its face's first use.
    std::vector<std::pair<Index, std::size_t>> first;  // (first slot, group start)
    for (std::size_t i = 0; i < slots.size(); ++i)
      if (i == 0 || slots[i].first != slots[i - 1].first) first.push_back({slots[i].second, i});
    std::sort(first.begin(), first.end());
    std::vector<TableIndex> id_of_group_start(slots.size(), -1);
    face_vertices_.resize(first.size());
    for (std::size_t id = 0; id < first.size(); ++id) {
      id_of_group_start[first[id].second] = static_cast<TableIndex>(id);
      const Index slot = first[id].first;
      for (int j = 0; j < 4; ++j)
        face_vertices_[id][static_cast<std::size_t>(j)] = mesh.cells(slot / 6, local[slot % 6][j]);
    }
    TableIndex id = -1;
    for (std::size_t i = 0; i < slots.size(); ++i) {
      if (id_of_group_start[i] >= 0) id = id_of_group_start[i];
      cell_face_(slots[i].second / 6, slots[i].second % 6) = id;
      if (id_of_group_start[i] >= 0) sorted_.push_back({slots[i].first, id});
    }
  }
  Index num_faces() const { return static_cast<Index>(face_vertices_.size()); }
  Index cell_face(Index cell, int f) const { return cell_face_(cell, f); }
  const std::array<TableIndex, 4>& vertices(Index face) const {
    return face_vertices_[static_cast<std::size_t>(face)];
  }
  /// The face with vertices v[0..3] (any order), or -1.
  Index find(const TableIndex* v) const {
    Key k{v[0], v[1], v[2], v[3]};
    std::sort(k.begin(), k.end());
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::pair<Key, TableIndex>{k, -1});
    return it != sorted_.end() && it->first == k ? it->second : -1;
  }

 private:
  using Key = std::array<TableIndex, 4>;
  IndexTable cell_face_;
  std::vector<std::array<TableIndex, 4>> face_vertices_;
  std::vector<std::pair<Key, TableIndex>> sorted_;  // by key
};

// ---- Refinement ------------------------------------------------------------

/// The fine mesh's EdgeNumbering without searching (triangles): fine edges are
/// halves of coarse edges (key 2E + 0 at the coarse edge's smaller vertex,
/// 2E + 1 at the other) or one of three edges inside a coarse cell (key
/// 2ne + 3c + {0: m01–m12, 1: m12–m20, 2: m20–m01}); ids are then given in
/// the order the fine cells first use the edges, as EdgeNumbering(fine) would.
EdgeNumbering number_fine_edges(const Mesh<2>& coarse, const EdgeNumbering& edges, const Mesh<2>& fine) {
  const Index nc = coarse.num_cells(), ne = edges.num_edges();
  const Index keys = 2 * ne + 3 * nc;
  checked_table_size(keys, "refine_uniformly: fine edges");
  std::vector<TableIndex> id_of_key(static_cast<std::size_t>(keys), -1);
  IndexTable cell_edge(fine.num_cells(), 3);
  std::vector<std::array<Index, 2>> edge_vertices;
  edge_vertices.reserve(static_cast<std::size_t>(keys));
  const auto half = [&](Index E, Index x) { return 2 * E + (x == edges.vertices(E)[0] ? 0 : 1); };
  for (Index c = 0; c < nc; ++c) {
    const TableIndex* v = &coarse.cells(c, 0);
    const Index E0 = edges.cell_edge(c, 0), E1 = edges.cell_edge(c, 1), E2 = edges.cell_edge(c, 2);
    const Index ka = 2 * ne + 3 * c, kb = ka + 1, kc = ka + 2;
    // Local edges (0,1), (1,2), (2,0) of the children in the layout of refine_uniformly.
    const Index child_keys[4][3] = {{half(E0, v[0]), kc, half(E2, v[0])},
                                    {half(E0, v[1]), half(E1, v[1]), ka},
                                    {kb, half(E1, v[2]), half(E2, v[2])},
                                    {ka, kb, kc}};
    for (Index k = 0; k < 4; ++k) {
      const Index f = 4 * c + k;
      for (Index e = 0; e < 3; ++e) {
        TableIndex& id = id_of_key[static_cast<std::size_t>(child_keys[k][e])];
        if (id < 0) {
          id = static_cast<TableIndex>(edge_vertices.size());
          const Index a = fine.cells(f, e), b = fine.cells(f, (e + 1) % 3);
          edge_vertices.push_back({std::min(a, b), std::max(a, b)});
        }
        cell_edge(f, e) = id;
      }
    }
  }
  // Fine boundary facets 2f, 2f + 1 are the halves of coarse facet f at its
  // first and second vertex.
  const Index nb = coarse.num_boundary_facets();
  std::vector<TableIndex> facet_edge(static_cast<std::size_t>(2 * nb));
  for (Index f = 0; f < nb; ++f) {
    const Index a = coarse.boundary_facets(f, 0), b = coarse.boundary_facets(f, 1);
    const Index E = edges.boundary_facet_edge(f, a, b);
    facet_edge[static_cast<std::size_t>(2 * f)] = id_of_key[static_cast<std::size_t>(half(E, a))];
    facet_edge[static_cast<std::size_t>(2 * f + 1)] = id_of_key[static_cast<std::size_t>(half(E, b))];
  }
  return EdgeNumbering(std::move(cell_edge), std::move(edge_vertices), std::move(facet_edge));
}

/// Step 1 of refine_uniformly for cells refined by `table`: the fine cells,
/// with fine vertices numbered in the order the fine cells first use the
/// coarse *nodes* (coarse vertex v, midpoint of coarse edge e at node nv + e,
/// face centre at nv + ne + face, cell centre at nv + ne + nfaces + c). Node
/// order would put the vertices of a cell up to a whole mesh apart in memory,
/// and every vertex- or DOF-ordered loop over the level (sparsity pattern,
/// assembly scatter, matrix rows, prolongation) would jump across the mesh;
/// the cells are ordered hierarchically (children of c together), so first
/// use keeps a cell's vertices, and its matrix rows, together. The children
/// of c first use its nodes in a fixed order (first_use(table)), so one pass
/// numbers them and writes the cells at their final numbers.
template <const RefinementTable& table, int dim>
void write_children(const Mesh<dim>& coarse, const EdgeNumbering& edges, const QuadFaces* faces,
                    RefinedMesh<dim>& out) {
  constexpr int nvc = table.vertices, ncv = table.vertices * table.children;
  constexpr int first_edge = table.vertices, first_face = first_edge + table.edges,
                centre = first_face + table.faces;
  static constexpr FirstUse order = first_use(table);
  const Index nv = coarse.num_vertices(), ne = edges.num_edges(), nc = coarse.num_cells();
  const Index nfaces = faces ? faces->num_faces() : 0;
  std::vector<TableIndex>& vertex_of = out.fine_vertex_of_node;
  TableIndex next = 0;
  std::vector<TableIndex>& first_new = out.first_new_vertex;
  first_new.resize(static_cast<std::size_t>(nc) + 1);
  for (Index c = 0; c < nc; ++c) {
    first_new[static_cast<std::size_t>(c)] = next;
    const TableIndex* v = &coarse.cells(c, 0);
    std::array<TableIndex, RefinementTable::kMaxNodes> local;
#pragma GCC unroll 32
    for (int i = 0; i < order.count; ++i) {
      const int l = order.node[static_cast<std::size_t>(i)];
      Index node;
      if (l < first_edge)
        node = v[l];
      else if (l < first_face)
        node = nv + edges.cell_edge(c, l - first_edge);
      else if (l < centre)
        node = nv + ne + faces->cell_face(c, l - first_face);
      else
        node = nv + ne + nfaces + c;
      TableIndex& w = vertex_of[static_cast<std::size_t>(node)];
      if (w < 0) w = next++;
      local[static_cast<std::size_t>(l)] = w;
    }
    TableIndex* cells = &out.mesh.cells(table.children * c, 0);
#pragma GCC unroll 64
    for (int i = 0; i < ncv; ++i)
      cells[i] = local[static_cast<std::size_t>(
          table.child_nodes[static_cast<std::size_t>(i / nvc)][static_cast<std::size_t>(i % nvc)])];
  }
  first_new[static_cast<std::size_t>(nc)] = next;
  for (TableIndex& w : vertex_of)  // a coarse vertex in no cell keeps a place at the end
    if (w < 0) w = next++;
}

/// The boundary facets of a 3D refinement: each into 4 by its own table
/// (triangle or quadrilateral, in the facet's outward vertex order), tags kept.
void refine_facets(const Mesh<3>& coarse, const EdgeNumbering& edges, const QuadFaces* faces,
                   RefinedMesh<3>& out) {
  const CellType ft = facet_type(coarse.cell_type);
  const RefinementTable& t = refinement_table(ft);
  const auto& facet_edges = cell_edges(ft);
  const Index nv = coarse.num_vertices(), ne = edges.num_edges(), nb = coarse.num_boundary_facets();
  const std::vector<TableIndex>& vertex_of = out.fine_vertex_of_node;
  Mesh<3>& fine = out.mesh;
  fine.boundary_facets.resize(t.children * nb, t.vertices);
  fine.facet_tags.resize(static_cast<std::size_t>(t.children * nb));
  std::array<Index, RefinementTable::kMaxNodes> node{};
  for (Index f = 0; f < nb; ++f) {
    const TableIndex* v = &coarse.boundary_facets(f, 0);
    for (int k = 0; k < t.vertices; ++k) node[static_cast<std::size_t>(k)] = v[k];
    for (int e = 0; e < t.edges; ++e) {
      const Index id = edges.find(v[facet_edges[e][0]], v[facet_edges[e][1]]);
      require(id >= 0,
              "refine_uniformly: boundary facet " + std::to_string(f) + " is not a face of the mesh");
      node[static_cast<std::size_t>(t.vertices + e)] = nv + id;
    }
    if (t.centres) {
      const Index id = faces->find(v);
      require(id >= 0,
              "refine_uniformly: boundary facet " + std::to_string(f) + " is not a face of the mesh");
      node[static_cast<std::size_t>(t.vertices + t.edges)] = nv + ne + id;
    }
    for (int k = 0; k < t.children; ++k) {
      const Index child = t.children * f + k;
      for (int j = 0; j < t.vertices; ++j)
        fine.boundary_facets(child, j) = vertex_of[static_cast<std::size_t>(node[static_cast<std::size_t>(
            t.child_nodes[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)])])];
      fine.facet_tags[static_cast<std::size_t>(child)] = coarse.facet_tags[static_cast<std::size_t>(f)];
    }
  }
}

/// The boundary facets of a 2D refinement: each edge into its two halves.
void refine_facets(const Mesh<2>& coarse, const EdgeNumbering& edges, const QuadFaces*, RefinedMesh<2>& out) {
  const Index nv = coarse.num_vertices(), nb = coarse.num_boundary_facets();
  const std::vector<TableIndex>& vertex_of = out.fine_vertex_of_node;
  Mesh<2>& fine = out.mesh;
  fine.boundary_facets.resize(2 * nb, 2);
  fine.facet_tags.resize(static_cast<std::size_t>(2 * nb));
  for (Index f = 0; f < nb; ++f) {
    const Index a = coarse.boundary_facets(f, 0), b = coarse.boundary_facets(f, 1);
    const Index e = edges.boundary_facet_edge(f, a, b);
    require(e >= 0, "refine_uniformly: boundary facet is not an edge of the mesh");
    const Index fa = vertex_of[static_cast<std::size_t>(a)], fb = vertex_of[static_cast<std::size_t>(b)],
                fm = vertex_of[static_cast<std::size_t>(nv + e)];
    fine.boundary_facets.row(2 * f) << fa, fm;
    fine.boundary_facets.row(2 * f + 1) << fm, fb;
    fine.facet_tags[2 * f] = fine.facet_tags[2 * f + 1] = coarse.facet_tags[f];
  }
}

}  // namespace

const RefinementTable& refinement_table(CellType type) {
  // The tables' edges and faces must be reference_cell.hpp's (checked once).
  static const bool consistent = [] {
    for (CellType t :
         {CellType::triangle, CellType::quadrilateral, CellType::tetrahedron, CellType::hexahedron}) {
      const DoubledCell& c = doubled_cell(t);
      const auto& e = cell_edges(t);
      bool ok = static_cast<int>(e.size()) == c.edges;
      for (int i = 0; ok && i < c.edges; ++i) ok = e[i] == c.edge[static_cast<std::size_t>(i)];
      for (int f = 0; ok && f < c.faces; ++f)
        for (int j = 0; j < 4; ++j) ok = ok && cell_faces(t)[f][j] == c.face[static_cast<std::size_t>(f)][j];
      if (!ok) return false;
    }
    return true;
  }();
  require(consistent, "refinement_table: the refinement tables disagree with cell_edges / cell_faces");
  switch (type) {
    case CellType::triangle: return kTriangleTable;
    case CellType::quadrilateral: return kQuadrilateralTable;
    case CellType::tetrahedron: return kTetrahedronTable;
    case CellType::hexahedron: return kHexahedronTable;
  }
  throw Error("refinement_table: unknown cell type");
}

template <int dim>
RefinedMesh<dim> refine_uniformly(const Mesh<dim>& coarse, const EdgeNumbering* coarse_edges,
                                  bool number_fine) {
  coarse.require_whole("refine_uniformly");
  const CellType type = coarse.cell_type;
  require(cell_dimension(type) == dim,
          "refine_uniformly: a " + to_string(type) + " mesh in " + std::to_string(dim) + "D");
  const RefinementTable& table = refinement_table(type);
  std::optional<EdgeNumbering> own_edges;
  if (!coarse_edges) coarse_edges = &own_edges.emplace(coarse);
  const EdgeNumbering& edges = *coarse_edges;
  require(edges.num_cells() == coarse.num_cells(), "refine_uniformly: the edge numbering is not the mesh's");
  std::optional<QuadFaces> faces;
  if constexpr (dim == 3)
    if (table.faces) faces.emplace(coarse);
  const Index nv = coarse.num_vertices(), ne = edges.num_edges(), nc = coarse.num_cells();
  const Index nfaces = faces ? faces->num_faces() : 0;

  RefinedMesh<dim> out;
  Mesh<dim>& fine = out.mesh;
  fine.cell_type = type;
  const Index nf_vertices = nv + ne + nfaces + (table.centres ? nc : 0);
  checked_table_size(nf_vertices, "refine_uniformly: fine vertices");
  checked_table_size(table.children * nc, "refine_uniformly: fine cells");

  // 1. The fine cells and the fine vertex numbers (write_children).
  fine.cells.resize(table.children * nc, table.vertices);
  prefault(fine.cells.data(), static_cast<std::size_t>(fine.cells.size()) * sizeof(TableIndex));
  out.fine_vertex_of_node.assign(static_cast<std::size_t>(nf_vertices), -1);
  const QuadFaces* f = faces ? &*faces : nullptr;
  if constexpr (dim == 2) {
    if (type == CellType::triangle)
      write_children<kTriangleTable>(coarse, edges, f, out);
    else
      write_children<kQuadrilateralTable>(coarse, edges, f, out);
  } else {
    if (type == CellType::tetrahedron)
      write_children<kTetrahedronTable>(coarse, edges, f, out);
    else
      write_children<kHexahedronTable>(coarse, edges, f, out);
  }
  const std::vector<TableIndex>& vertex_of = out.fine_vertex_of_node;

  // 2. Positions, written once at the final numbers: the coarse cells' P1/Q1
  // geometry at the nodes, so the children tile their parents exactly.
  fine.vertices.resize(nf_vertices, dim);
  prefault(fine.vertices.data(), static_cast<std::size_t>(fine.vertices.size()) * sizeof(double));
  for (Index v = 0; v < nv; ++v)
    fine.vertices.row(vertex_of[static_cast<std::size_t>(v)]) = coarse.vertices.row(v);
  for (Index e = 0; e < ne; ++e) {
    const auto& ev = edges.vertices(e);
    fine.vertices.row(vertex_of[static_cast<std::size_t>(nv + e)]) =
        0.5 * (coarse.vertices.row(ev[0]) + coarse.vertices.row(ev[1]));
  }
  for (Index g = 0; g < nfaces; ++g) {
    const auto& fv = faces->vertices(g);
    fine.vertices.row(vertex_of[static_cast<std::size_t>(nv + ne + g)]) =
        0.25 * (coarse.vertices.row(fv[0]) + coarse.vertices.row(fv[1]) + coarse.vertices.row(fv[2]) +
                coarse.vertices.row(fv[3]));
  }
  if (table.centres)
    for (Index c = 0; c < nc; ++c) {
      const TableIndex* v = &coarse.cells(c, 0);
      Eigen::Matrix<Real, 1, dim> sum = coarse.vertices.row(v[0]);
      for (int k = 1; k < table.vertices; ++k) sum += coarse.vertices.row(v[k]);
      fine.vertices.row(vertex_of[static_cast<std::size_t>(nv + ne + nfaces + c)]) =
          (1.0 / table.vertices) * sum;
    }

  // 3. Boundary facets.
  refine_facets(coarse, edges, f, out);
  if constexpr (dim == 2)
    if (number_fine && type == CellType::triangle)
      out.fine_edges.emplace(number_fine_edges(coarse, edges, fine));
  return out;
}

template <int dim>
const Points<dim>& child_reference_vertices(CellType type, int child) {
  require(cell_dimension(type) == dim,
          "child_reference_vertices: a " + to_string(type) + " in " + std::to_string(dim) + "D");
  const RefinementTable& t = refinement_table(type);
  if (child < 0 || child >= t.children)
    throw Error("child_reference_vertices: child " + std::to_string(child) + " of a " + to_string(type) +
                " is not in 0.." + std::to_string(t.children - 1));
  // One table per cell type of this dimension, built on first use.
  static const auto all = [] {
    std::array<std::vector<Points<dim>>, 4> out;
    for (CellType ct :
         {CellType::triangle, CellType::quadrilateral, CellType::tetrahedron, CellType::hexahedron}) {
      if (cell_dimension(ct) != dim) continue;
      const RefinementTable& r = refinement_table(ct);
      const auto pos = node_positions(doubled_cell(ct));
      auto& children = out[static_cast<std::size_t>(ct)];
      children.resize(static_cast<std::size_t>(r.children));
      for (int k = 0; k < r.children; ++k) {
        Points<dim>& p = children[static_cast<std::size_t>(k)];
        p.resize(r.vertices, dim);
        for (int j = 0; j < r.vertices; ++j)
          for (int d = 0; d < dim; ++d)
            p(j, d) = 0.5 * pos[static_cast<std::size_t>(r.child_nodes[static_cast<std::size_t>(
                                k)][static_cast<std::size_t>(j)])][static_cast<std::size_t>(d)];
      }
    }
    return out;
  }();
  return all[static_cast<std::size_t>(type)][static_cast<std::size_t>(child)];
}

template RefinedMesh<2> refine_uniformly(const Mesh<2>&, const EdgeNumbering*, bool);
template RefinedMesh<3> refine_uniformly(const Mesh<3>&, const EdgeNumbering*, bool);
template const Points<2>& child_reference_vertices<2>(CellType, int);
template const Points<3>& child_reference_vertices<3>(CellType, int);

void order_for_refinement(Mesh<3>& mesh) {
  if (mesh.cell_type != CellType::tetrahedron) return;
  // The new vertex order that makes each pair of opposite edges {02, 13}:
  // {01, 23}, {02, 13}, {03, 12}; each an even permutation.
  constexpr int kOrder[3][4] = {{0, 3, 1, 2}, {0, 1, 2, 3}, {0, 2, 3, 1}};
  for (Index c = 0; c < mesh.num_cells(); ++c) {
    const auto x = [&](int k) { return mesh.vertices.row(mesh.cells(c, k)); };
    // Twice the distance between the midpoints of edges ab and de.
    const auto diagonal = [&](int a, int b, int d, int e) {
      return (x(a) + x(b) - x(d) - x(e)).squaredNorm();
    };
    const double length[3] = {diagonal(0, 1, 2, 3), diagonal(0, 2, 1, 3), diagonal(0, 3, 1, 2)};
    int best = 1;  // ties keep the given order
    for (int k : {0, 2})
      if (length[k] < length[best]) best = k;
    const auto old = mesh.cells.row(c).eval();
    for (int j = 0; j < 4; ++j) mesh.cells(c, j) = old(kOrder[best][j]);
  }
}

}  // namespace warpfem
