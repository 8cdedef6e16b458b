#include "apps/study_target_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "core/log.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/tetgen_mesher.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/hierarchy/polyhedron_parts.hpp"

namespace warpfem::apps {

namespace {

/// The mesh of the target whose cells are bounded by `cell_size` (an area or a volume).
template <int dim>
Mesh<dim> mesh_with_cell_size(const Domain<dim>& source, const Domain<dim>& target, double cell_size) {
  if constexpr (dim == 2) {
    (void)source;  // mesh_polygon tags every facet with its polygon edge, the source's part
    PolygonMeshOptions options;
    options.max_edge_length = std::sqrt(4 * cell_size / std::sqrt(3.0));  // the equilateral triangle's edge
    return mesh_polygon(target, options);
  } else {
    TetrahedralMeshOptions options;
    options.max_volume = cell_size;
    options.keep_surface = false;  // split the surface too: the cells at the boundary shrink with the bound
    options.triangle_tags = fem::boundary_parts(source).triangle_part;
    return mesh_polyhedron(target, options);
  }
}

template <int dim>
Index dof_count(const Mesh<dim>& mesh, int order) {
  return fem::DofMap<dim>(mesh, fem::LagrangeElement<dim>(mesh.cell_type, order)).num_dofs();
}

}  // namespace

template <int dim>
Mesh<dim> mesh_target_with_dofs(const Domain<dim>& source, const Domain<dim>& target, int order, Index dofs) {
  double measure = 0;
  if constexpr (dim == 2)
    measure = std::abs(target.signed_area());
  else
    measure = std::abs(target.signed_volume());
  // A first guess from a simplex mesh's count of vertices per cell, then a secant step on
  // log(DOFs) against log(size bound) (DOFs ∝ 1/size away from the coarsest meshes).
  double size = measure * (dim == 2 ? 2.0 : 6.0) * std::pow(order, dim) / static_cast<double>(dofs);
  Mesh<dim> best;
  double best_miss = INFINITY;
  double previous_size = 0, previous_log = 0;
  for (int trial = 0; trial < 8; ++trial) {
    Mesh<dim> mesh = mesh_with_cell_size<dim>(source, target, size);
    const Index n = dof_count(mesh, order);
    const double miss = std::log(static_cast<double>(n) / static_cast<double>(dofs));
    log::debug("target mesh trial ", trial, ": size bound ", size, ", ", n, " DOFs");
    if (std::abs(miss) < best_miss) {
      best_miss = std::abs(miss);
      best = std::move(mesh);
    }
    if (best_miss < 0.05) break;
    double slope = -1;  // d log(DOFs) / d log(size)
    if (trial > 0 && size != previous_size) {
      const double s = (miss - previous_log) / std::log(size / previous_size);
      if (s < -0.2 && s > -3) slope = s;  // a step function of the bound: keep the model's slope otherwise
    }
    previous_size = size;
    previous_log = miss;
    if (previous_size >= measure && miss > 0) break;  // no bound is active: the coarsest mesh
    size = std::min(measure, size * std::exp(-miss / slope));
  }
  return best;
}

template Mesh<2> mesh_target_with_dofs<2>(const Polygon&, const Polygon&, int, Index);
template Mesh<3> mesh_target_with_dofs<3>(const Polyhedron&, const Polyhedron&, int, Index);

}  // namespace warpfem::apps
