#include "fem/uniform_refinement.hpp"

#include <vector>

#include "core/error.hpp"
#include "fem/edge_numbering.hpp"

namespace warpfem::fem {

namespace {
/// Renumbers the fine vertices in the order the fine cells first use them.
/// Built above, they come as [coarse vertices, edge midpoints, centres]: the
/// vertices of one cell lie up to a whole mesh apart in memory, and every
/// vertex- or DOF-ordered loop over a fine level (sparsity pattern, assembly
/// scatter, matrix rows, SpMV) jumps across the mesh. The cells are already
/// ordered hierarchically (children 4c … 4c+3 of cell c), so first use keeps
/// a cell's vertices, and hence its matrix rows, close together.
void number_vertices_by_first_use(RefinedMesh& r) {
  Mesh<2>& m = r.mesh;
  const Index nv = m.num_vertices();
  std::vector<Index> new_index(static_cast<std::size_t>(nv), -1);
  Index next = 0;
  for (Index c = 0; c < m.num_cells(); ++c)
    for (Index k = 0; k < m.cells.cols(); ++k) {
      Index& v = m.cells(c, k);
      if (new_index[v] < 0) new_index[v] = next++;
      v = new_index[v];
    }
  for (Index v = 0; v < nv; ++v)  // a vertex used by no cell keeps a place at the end
    if (new_index[v] < 0) new_index[v] = next++;
  Points<2> vertices(nv, 2);
  std::vector<VertexParents> parents(static_cast<std::size_t>(nv));
  for (Index v = 0; v < nv; ++v) {
    vertices.row(new_index[v]) = m.vertices.row(v);
    parents[static_cast<std::size_t>(new_index[v])] = r.vertex_parents[static_cast<std::size_t>(v)];
  }
  m.vertices = std::move(vertices);
  r.vertex_parents = std::move(parents);
  for (Index f = 0; f < m.num_boundary_facets(); ++f)
    for (Index k = 0; k < m.boundary_facets.cols(); ++k)
      m.boundary_facets(f, k) = new_index[m.boundary_facets(f, k)];
  r.fine_vertex_of_node = std::move(new_index);  // the nodes were built as vertices in this order
}
}  // namespace

RefinedMesh refine_uniformly(const Mesh<2>& coarse) {
  const bool quads = coarse.cell_type == CellType::quadrilateral;
  require(coarse.cell_type == CellType::triangle || quads, "refine_uniformly: unsupported cell type");
  const EdgeNumbering edges(coarse);
  const Index nv = coarse.num_vertices(), ne = edges.num_edges(), nc = coarse.num_cells();

  RefinedMesh out;
  Mesh<2>& fine = out.mesh;
  fine.cell_type = coarse.cell_type;
  const Index nf_vertices = nv + ne + (quads ? nc : 0);
  fine.vertices.resize(nf_vertices, 2);
  out.vertex_parents.resize(static_cast<std::size_t>(nf_vertices));
  for (Index v = 0; v < nv; ++v) {
    fine.vertices.row(v) = coarse.vertices.row(v);
    out.vertex_parents[v] = {{v, 0, 0, 0}, 1};
  }
  for (Index e = 0; e < ne; ++e) {
    const auto& ev = edges.vertices(e);
    fine.vertices.row(nv + e) = 0.5 * (coarse.vertices.row(ev[0]) + coarse.vertices.row(ev[1]));
    out.vertex_parents[nv + e] = {{ev[0], ev[1], 0, 0}, 2};
  }
  fine.cells.resize(4 * nc, quads ? 4 : 3);
  out.cell_parent.resize(static_cast<std::size_t>(4 * nc));
  for (Index c = 0; c < nc; ++c) {
    const Index* v = &coarse.cells(c, 0);
    for (int k = 0; k < 4; ++k) out.cell_parent[4 * c + k] = c;
    if (!quads) {
      const Index m01 = nv + edges.cell_edge(c, 0), m12 = nv + edges.cell_edge(c, 1),
                  m20 = nv + edges.cell_edge(c, 2);
      fine.cells.row(4 * c + 0) << v[0], m01, m20;
      fine.cells.row(4 * c + 1) << m01, v[1], m12;
      fine.cells.row(4 * c + 2) << m20, m12, v[2];
      fine.cells.row(4 * c + 3) << m01, m12, m20;
    } else {
      const Index centre = nv + ne + c;
      fine.vertices.row(centre) = 0.25 * (coarse.vertices.row(v[0]) + coarse.vertices.row(v[1]) +
                                          coarse.vertices.row(v[2]) + coarse.vertices.row(v[3]));
      out.vertex_parents[centre] = {{v[0], v[1], v[2], v[3]}, 4};
      Index m[4];
      for (int k = 0; k < 4; ++k) m[k] = nv + edges.cell_edge(c, k);
      fine.cells.row(4 * c + 0) << v[0], m[0], centre, m[3];
      fine.cells.row(4 * c + 1) << m[0], v[1], m[1], centre;
      fine.cells.row(4 * c + 2) << centre, m[1], v[2], m[2];
      fine.cells.row(4 * c + 3) << m[3], centre, m[2], v[3];
    }
  }
  const Index nb = coarse.num_boundary_facets();
  fine.boundary_facets.resize(2 * nb, 2);
  fine.facet_tags.resize(static_cast<std::size_t>(2 * nb));
  for (Index f = 0; f < nb; ++f) {
    const Index a = coarse.boundary_facets(f, 0), b = coarse.boundary_facets(f, 1);
    const Index e = edges.find(a, b);
    require(e >= 0, "refine_uniformly: boundary facet is not an edge of the mesh");
    fine.boundary_facets.row(2 * f) << a, nv + e;
    fine.boundary_facets.row(2 * f + 1) << nv + e, b;
    fine.facet_tags[2 * f] = fine.facet_tags[2 * f + 1] = coarse.facet_tags[f];
  }
  number_vertices_by_first_use(out);
  return out;
}

}  // namespace warpfem::fem
