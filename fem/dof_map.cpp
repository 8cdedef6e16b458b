#include "fem/dof_map.hpp"

#include "core/error.hpp"

namespace warpfem::fem {

DofMap::DofMap(const Mesh<2>& mesh, const LagrangeElement<2>& element) : element_(element) {
  require(mesh.cell_type == element.cell_type(),
          "DofMap: element " + element.name() + " does not match " + to_string(mesh.cell_type) + " cells");
  const int per_edge = element.dofs_per_edge(), interior = element.interior_dofs();
  if (per_edge > 0) edges_.emplace(mesh);
  const Index nv = mesh.num_vertices(), ne = edges_ ? edges_->num_edges() : 0, nc = mesh.num_cells();
  num_dofs_ = checked_table_size(nv + ne * per_edge + nc * interior, "DofMap: DOFs of " + element.name());
  const int nloc = element.num_dofs();
  const int nvert = element.num_vertex_dofs();
  const auto& edges = cell_edges(mesh.cell_type);
  if (per_edge == 0 && interior == 0 && nloc == nvert && mesh.cells.cols() == nvert) {
    vertex_dofs_ = &mesh;  // P1/Q1: the DOFs are the vertices, numbered as the mesh numbers them
    return;
  }
  cell_dofs_.resize(nc, nloc);
  for (Index c = 0; c < nc; ++c) {
    for (int k = 0; k < nvert; ++k) cell_dofs_(c, k) = mesh.cells(c, k);
    for (int e = 0; e < static_cast<int>(edges.size()) && per_edge > 0; ++e)
      cell_dofs_(c, nvert + e) = nv + edges_->cell_edge(c, e);
    for (int k = 0; k < interior; ++k)
      cell_dofs_(c, nloc - interior + k) = nv + ne * per_edge + c * interior + k;
  }
  // Node positions: map the reference nodes through the straight cell geometry.
  const LagrangeElement<2> geo(mesh.cell_type, 1);
  const MatrixX N = geo.values(element.nodes());
  dof_points_.resize(num_dofs_, 2);
  for (Index c = 0; c < nc; ++c)
    for (int k = 0; k < nloc; ++k) {
      Point<2> x = Point<2>::Zero();
      for (int v = 0; v < nvert; ++v) x += N(k, v) * mesh.vertex(mesh.cells(c, v));
      dof_points_.row(cell_dofs_(c, k)) = x.transpose();
    }
}

std::vector<Index> DofMap::facet_dofs(const Mesh<2>& mesh, Index facet) const {
  const Index a = mesh.boundary_facets(facet, 0), b = mesh.boundary_facets(facet, 1);
  std::vector<Index> out{a, b};
  if (edges_) {
    const Index e = edges_->find(a, b);
    require(e >= 0, "DofMap: boundary facet is not a mesh edge");
    out.push_back(mesh.num_vertices() + e);
  }
  return out;
}

namespace {
template <int NV>
void straight_cell_geometry(const Mesh<2>& mesh, Index cell, Index nq, const MatrixX& N,
                            const std::array<MatrixX, 2>& dN, Points<2>& x0, Jacobians<2>& JG, Index offset) {
  double vx[NV], vy[NV];  // the cell's vertices, read once
  const TableIndex* c = &mesh.cells(cell, 0);
  for (int k = 0; k < NV; ++k) {
    vx[k] = mesh.vertices(c[k], 0);
    vy[k] = mesh.vertices(c[k], 1);
  }
  const double *n = N.data(), *du = dN[0].data(), *dv = dN[1].data();  // column-major: (q, k) at k nq + q
  const Index ldx = x0.rows(), ldj = JG.rows();
  double* X = x0.data() + offset;
  double* G = JG.data() + offset;
  for (Index q = 0; q < nq; ++q) {
    double x = 0, y = 0, j00 = 0, j01 = 0, j10 = 0, j11 = 0;
    for (int k = 0; k < NV; ++k) {
      const double w = n[k * nq + q], a = du[k * nq + q], b = dv[k * nq + q];
      x += w * vx[k], y += w * vy[k];
      j00 += vx[k] * a, j01 += vx[k] * b;
      j10 += vy[k] * a, j11 += vy[k] * b;
    }
    X[q] = x, X[ldx + q] = y;
    G[q] = j00, G[ldj + q] = j01, G[2 * ldj + q] = j10, G[3 * ldj + q] = j11;
  }
}
}  // namespace

void simple_cell_geometry(const Mesh<2>& mesh, Index cell, const Points<2>& xi, const MatrixX& N,
                          const std::array<MatrixX, 2>& dN, Points<2>& x0, Jacobians<2>& JG, Index offset) {
  // The vertex count as a compile-time constant: the inner loops unroll.
  if (vertices_per_cell(mesh.cell_type) == 3)
    straight_cell_geometry<3>(mesh, cell, xi.rows(), N, dN, x0, JG, offset);
  else
    straight_cell_geometry<4>(mesh, cell, xi.rows(), N, dN, x0, JG, offset);
}

}  // namespace warpfem::fem
