#include "fem/output_mesh.hpp"

#include <unordered_map>

namespace warpfem::fem {

OutputMesh make_output_mesh(const Mesh<2>& mesh, const DofDistribution& dist, const mapping::Map<2>& map,
                            int order) {
  OutputMesh out;
  out.cell_type = mesh.cell_type;
  out.order = order;
  const DofMap nodes(mesh, LagrangeElement(mesh.cell_type, order));
  const int nloc = nodes.element().num_dofs();
  const auto& cells = dist.local_cells();
  out.cells.resize(static_cast<Index>(cells.size()), nloc);
  out.cell_ids = cells;
  std::unordered_map<Index, Index> local;
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (int k = 0; k < nloc; ++k) {
      const Index d = nodes.cell_dofs()(cells[i], k);
      auto [it, inserted] = local.try_emplace(d, static_cast<Index>(out.node_source_.size()));
      if (inserted) out.node_source_.emplace_back(static_cast<Index>(i), k);
      out.cells(static_cast<Index>(i), k) = it->second;
    }
  const Index n = static_cast<Index>(out.node_source_.size());
  out.reference_points.resize(n, 2);
  for (const auto& [d, i] : local) out.reference_points.row(i) = nodes.dof_points().row(d);
  Jacobians<2> J;
  map.eval_with_jacobian(out.reference_points, out.points, J);
  out.map_det = J.col(0).cwiseProduct(J.col(3)) - J.col(1).cwiseProduct(J.col(2));
  return out;
}

VectorX OutputMesh::interpolate(const DofMap& dofs, const DofDistribution& dist,
                                const VectorX& relevant_values) const {
  const LagrangeElement out_element(cell_type, order);
  const MatrixX phi = dofs.element().values(out_element.nodes());  // output nodes x element dofs
  VectorX values(static_cast<Index>(node_source_.size()));
  for (std::size_t i = 0; i < node_source_.size(); ++i) {
    const auto [cell_index, k] = node_source_[i];
    const Index c = cell_ids[static_cast<std::size_t>(cell_index)];
    double v = 0;
    for (Index j = 0; j < phi.cols(); ++j)
      v += phi(k, j) * relevant_values(dist.relevant_index(dofs.cell_dofs()(c, j)));
    values(static_cast<Index>(i)) = v;
  }
  return values;
}

}  // namespace warpfem::fem
