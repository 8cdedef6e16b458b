#include "fem/uniform_refinement.hpp"

#include <array>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/prefault.hpp"
#include "fem/edge_numbering.hpp"

namespace warpfem::fem {

RefinedMesh refine_uniformly(const Mesh<2>& coarse) {
  const bool quads = coarse.cell_type == CellType::quadrilateral;
  require(coarse.cell_type == CellType::triangle || quads, "refine_uniformly: unsupported cell type");
  const EdgeNumbering edges(coarse);
  const Index nv = coarse.num_vertices(), ne = edges.num_edges(), nc = coarse.num_cells();

  RefinedMesh out;
  Mesh<2>& fine = out.mesh;
  fine.cell_type = coarse.cell_type;
  const Index nf_vertices = nv + ne + (quads ? nc : 0);
  checked_table_size(nf_vertices, "refine_uniformly: fine vertices");
  checked_table_size(4 * nc, "refine_uniformly: fine cells");

  // 1. Fine cells over the fine *nodes*: coarse vertex v, midpoint of coarse
  // edge e at nv + e, centre of quadrilateral c at nv + ne + c.
  fine.cells.resize(4 * nc, quads ? 4 : 3);
  prefault(fine.cells.data(), static_cast<std::size_t>(fine.cells.size()) * sizeof(TableIndex));
  for (Index c = 0; c < nc; ++c) {
    const TableIndex* v = &coarse.cells(c, 0);
    if (!quads) {  // layouts: child_reference_vertices()
      const Index m01 = nv + edges.cell_edge(c, 0), m12 = nv + edges.cell_edge(c, 1),
                  m20 = nv + edges.cell_edge(c, 2);
      fine.cells.row(4 * c + 0) << v[0], m01, m20;
      fine.cells.row(4 * c + 1) << m01, v[1], m12;
      fine.cells.row(4 * c + 2) << m20, m12, v[2];
      fine.cells.row(4 * c + 3) << m01, m12, m20;
    } else {
      const Index centre = nv + ne + c;  // layouts: child_reference_vertices()
      Index m[4];
      for (int k = 0; k < 4; ++k) m[k] = nv + edges.cell_edge(c, k);
      fine.cells.row(4 * c + 0) << v[0], m[0], centre, m[3];
      fine.cells.row(4 * c + 1) << m[0], v[1], m[1], centre;
      fine.cells.row(4 * c + 2) << centre, m[1], v[2], m[2];
      fine.cells.row(4 * c + 3) << m[3], centre, m[2], v[3];
    }
  }

  // 2. Fine vertices are numbered in the order the fine cells first use the
  // nodes. Node order would put the three vertices of a cell up to a whole
  // mesh apart in memory, and every vertex- or DOF-ordered loop over the level
  // (sparsity pattern, assembly scatter, matrix rows, prolongation) would jump
  // across the mesh; the cells are ordered hierarchically (children 4c … 4c+3
  // of c), so first use keeps a cell's vertices, and its matrix rows, together.
  std::vector<TableIndex>& vertex_of = out.fine_vertex_of_node;
  vertex_of.assign(static_cast<std::size_t>(nf_vertices), -1);
  TableIndex next = 0;
  for (Index c = 0; c < fine.num_cells(); ++c)
    for (Index k = 0; k < fine.cells.cols(); ++k) {
      TableIndex& node = fine.cells(c, k);
      TableIndex& v = vertex_of[static_cast<std::size_t>(node)];
      if (v < 0) v = next++;
      node = v;
    }
  for (TableIndex& v : vertex_of)  // a coarse vertex in no cell keeps a place at the end
    if (v < 0) v = next++;

  // 3. Positions, written once at the final numbers.
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
    const Index e = edges.find(a, b);
    require(e >= 0, "refine_uniformly: boundary facet is not an edge of the mesh");
    const Index fa = vertex_of[static_cast<std::size_t>(a)], fb = vertex_of[static_cast<std::size_t>(b)],
                fm = vertex_of[static_cast<std::size_t>(nv + e)];
    fine.boundary_facets.row(2 * f) << fa, fm;
    fine.boundary_facets.row(2 * f + 1) << fm, fb;
    fine.facet_tags[2 * f] = fine.facet_tags[2 * f + 1] = coarse.facet_tags[f];
  }
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

}  // namespace warpfem::fem
