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

}  // namespace

RefinedMesh refine_uniformly(const Mesh<2>& coarse, const EdgeNumbering* coarse_edges, bool number_fine) {
  coarse.require_whole("refine_uniformly");
  const bool quads = coarse.cell_type == CellType::quadrilateral;
  require(coarse.cell_type == CellType::triangle || quads, "refine_uniformly: unsupported cell type");
  std::optional<EdgeNumbering> own_edges;
  if (!coarse_edges) coarse_edges = &own_edges.emplace(coarse);
  const EdgeNumbering& edges = *coarse_edges;
  require(edges.num_cells() == coarse.num_cells(), "refine_uniformly: the edge numbering is not the mesh's");
  const Index nv = coarse.num_vertices(), ne = edges.num_edges(), nc = coarse.num_cells();

  RefinedMesh out;
  Mesh<2>& fine = out.mesh;
  fine.cell_type = coarse.cell_type;
  const Index nf_vertices = nv + ne + (quads ? nc : 0);
  checked_table_size(nf_vertices, "refine_uniformly: fine vertices");
  checked_table_size(4 * nc, "refine_uniformly: fine cells");

  // 1. The fine cells, with fine vertices numbered in the order the fine cells
  // first use the coarse *nodes* (coarse vertex v, midpoint of coarse edge e
  // at node nv + e, centre of quadrilateral c at nv + ne + c). Node order would
  // put the three vertices of a cell up to a whole mesh apart in memory, and
  // every vertex- or DOF-ordered loop over the level (sparsity pattern,
  // assembly scatter, matrix rows, prolongation) would jump across the mesh;
  // the cells are ordered hierarchically (children 4c … 4c+3 of c), so first
  // use keeps a cell's vertices, and its matrix rows, together. The children
  // of c first use its nodes in a fixed order (the layouts of
  // child_reference_vertices(): v0 m01 m20 v1 m12 v2 for a triangle), so one
  // pass numbers them and writes the cells at their final numbers.
  fine.cells.resize(4 * nc, quads ? 4 : 3);
  prefault(fine.cells.data(), static_cast<std::size_t>(fine.cells.size()) * sizeof(TableIndex));
  std::vector<TableIndex>& vertex_of = out.fine_vertex_of_node;
  vertex_of.assign(static_cast<std::size_t>(nf_vertices), -1);
  TableIndex next = 0;
  const auto number = [&](Index node) {
    TableIndex& v = vertex_of[static_cast<std::size_t>(node)];
    if (v < 0) v = next++;
    return v;
  };
  std::vector<TableIndex>& first_new = out.first_new_vertex;
  first_new.resize(static_cast<std::size_t>(nc) + 1);
  for (Index c = 0; c < nc; ++c) {
    first_new[static_cast<std::size_t>(c)] = next;
    const TableIndex* v = &coarse.cells(c, 0);
    TableIndex* out_cells = &fine.cells(4 * c, 0);
    if (!quads) {
      const TableIndex v0 = number(v[0]), m01 = number(nv + edges.cell_edge(c, 0)),
                       m20 = number(nv + edges.cell_edge(c, 2)), v1 = number(v[1]),
                       m12 = number(nv + edges.cell_edge(c, 1)), v2 = number(v[2]);
      const TableIndex children[12] = {v0, m01, m20, m01, v1, m12, m20, m12, v2, m01, m12, m20};
      std::copy(children, children + 12, out_cells);
    } else {
      const TableIndex v0 = number(v[0]), m0 = number(nv + edges.cell_edge(c, 0)), ce = number(nv + ne + c),
                       m3 = number(nv + edges.cell_edge(c, 3)), v1 = number(v[1]),
                       m1 = number(nv + edges.cell_edge(c, 1)), v2 = number(v[2]),
                       m2 = number(nv + edges.cell_edge(c, 2)), v3 = number(v[3]);
      const TableIndex children[16] = {v0, m0, ce, m3, m0, v1, m1, ce, ce, m1, v2, m2, m3, ce, m2, v3};
      std::copy(children, children + 16, out_cells);
    }
  }
  first_new[static_cast<std::size_t>(nc)] = next;
  for (TableIndex& v : vertex_of)  // a coarse vertex in no cell keeps a place at the end
    if (v < 0) v = next++;

  // 2. Positions, written once at the final numbers.
  fine.vertices.resize(nf_vertices, 2);
  prefault(fine.vertices.data(), static_cast<std::size_t>(fine.vertices.size()) * sizeof(double));
  for (Index v = 0; v < nv; ++v)
    fine.vertices.row(vertex_of[static_cast<std::size_t>(v)]) = coarse.vertices.row(v);
  for (Index e = 0; e < ne; ++e) {
    const auto& ev = edges.vertices(e);
    fine.vertices.row(vertex_of[static_cast<std::size_t>(nv + e)]) =
        0.5 * (coarse.vertices.row(ev[0]) + coarse.vertices.row(ev[1]));
  }
  if (quads)
    for (Index c = 0; c < nc; ++c) {
      const TableIndex* v = &coarse.cells(c, 0);
      fine.vertices.row(vertex_of[static_cast<std::size_t>(nv + ne + c)]) =
          0.25 * (coarse.vertices.row(v[0]) + coarse.vertices.row(v[1]) + coarse.vertices.row(v[2]) +
                  coarse.vertices.row(v[3]));
    }

  const Index nb = coarse.num_boundary_facets();
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
  if (number_fine && !quads) out.fine_edges.emplace(number_fine_edges(coarse, edges, fine));
  return out;
}

const Points<2>& child_reference_vertices(CellType type, int child) {
  if (child < 0 || child > 3)
    throw Error("child_reference_vertices: child " + std::to_string(child) + " is not in 0..3");
  // The layout of step 1 of refine_uniformly: vertices v0 v1 v2 (v3), edge
  // midpoints m01 = (1/2, 0), ..., and the quadrilateral's centre (1/2, 1/2).
  static const std::array<Points<2>, 4> triangle = [] {
    std::array<Points<2>, 4> t;
    for (auto& p : t) p.resize(3, 2);
    t[0] << 0, 0, 0.5, 0, 0, 0.5;      // v0, m01, m20
    t[1] << 0.5, 0, 1, 0, 0.5, 0.5;    // m01, v1, m12
    t[2] << 0, 0.5, 0.5, 0.5, 0, 1;    // m20, m12, v2
    t[3] << 0.5, 0, 0.5, 0.5, 0, 0.5;  // m01, m12, m20
    return t;
  }();
  static const std::array<Points<2>, 4> quadrilateral = [] {
    std::array<Points<2>, 4> q;
    for (auto& p : q) p.resize(4, 2);
    q[0] << 0, 0, 0.5, 0, 0.5, 0.5, 0, 0.5;  // v0, m0, centre, m3
    q[1] << 0.5, 0, 1, 0, 1, 0.5, 0.5, 0.5;  // m0, v1, m1, centre
    q[2] << 0.5, 0.5, 1, 0.5, 1, 1, 0.5, 1;  // centre, m1, v2, m2
    q[3] << 0, 0.5, 0.5, 0.5, 0.5, 1, 0, 1;  // m3, centre, m2, v3
    return q;
  }();
  require(type == CellType::triangle || type == CellType::quadrilateral,
          "child_reference_vertices: unsupported cell type");
  return (type == CellType::triangle ? triangle : quadrilateral)[static_cast<std::size_t>(child)];
}

}  // namespace warpfem
