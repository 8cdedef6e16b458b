#pragma once
// Coarse meshes of Ω0 that the map warps into good meshes of Ω1.
//
// A Delaunay mesh of Ω0 warped by a strongly distorting map (a square onto a
// gear) has long thin images near the boundary: the pulled-back Poisson
// coefficient det J J⁻¹J⁻ᵀ is anisotropic relative to the cells, and point
// smoothers, hence multigrid, lose their h-independence. Here the target
// polygon is meshed instead (CGAL constrained Delaunay, shape-bounded) and
// every vertex is pulled back through f⁻¹; the cells keep their connectivity.
// Uniform refinement in Ω0 then produces images that stay close to similar
// copies of those well-shaped triangles wherever f is smooth.

#include "core/mesh/mesh.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/polygon.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

struct PullbackReport {
  int fold_repairs = 0;       ///< rounds of refinement around cells that folded in Ω0
  int newton_iterations = 0;  ///< Newton iterations of the last batched inverse
  Real max_residual = 0;      ///< max ‖f(x) − y‖ over the pulled-back vertices
  /// Largest condition number of A_T⁻¹J_f over points inside a cell T, A_T the
  /// affine map onto T's straight target triangle: how far from affine f is
  /// over the coarse cells (≈ how much worse than the target triangles the
  /// images of their refinements can be shaped).
  Real max_distortion = 0;
  Real min_area_ratio = 0;  ///< min over cells of area in Ω0 / mean cell area in Ω0
};

/// Meshes `target` with `options` (lengths in Ω1 units) and pulls the mesh
/// back to Ω0 through the bijective `map` from `source` to `target`. Boundary
/// vertices land exactly on their source edge; facet tags are the edges'
/// indices as for mesh_polygon. Where a straight cell of Ω0 would fold (for
/// instance a target triangle with its three vertices on the boundary around a
/// corner that is straight in Ω0), the target mesh gets the cell's centroid as
/// an extra vertex and is pulled back again (up to 8 times). Throws warpfem::Error (key
/// mesh.max_edge_length) if a vertex cannot be inverted or cells still fold.
Mesh<2> pull_back_target_mesh(const Polygon& source, const Polygon& target, const mapping::Map<2>& map,
                              const PolygonMeshOptions& options, PullbackReport* report = nullptr);

}  // namespace warpfem::fem
