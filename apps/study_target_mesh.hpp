#pragma once
// The "target_mesh" baseline of a convergence study: standard FEM on a mesh of
// the exact domain itself (the target polygon or polyhedron, identity map),
// with about as many DOFs as a warped level. CGAL's Delaunay triangles in 2D,
// TetGen's tetrahedra in 3D; the size bound is found by a few trial meshes,
// since the DOFs a bound gives depend on the domain and the mesher.

#include <type_traits>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"
#include "core/polyhedron.hpp"

namespace warpfem::apps {

template <int dim>
using Domain = std::conditional_t<dim == 2, Polygon, Polyhedron>;

/// A mesh of `target` whose Lagrange space of `order` has about `dofs` DOFs
/// (the closest of the trials; fewer are impossible below the mesh of the
/// domain's own vertices). Boundary facets carry the boundary parts of `source`
/// (the target has the source's edges or triangles, in the same order), so the
/// config's boundary conditions select the same sides.
template <int dim>
Mesh<dim> mesh_target_with_dofs(const Domain<dim>& source, const Domain<dim>& target, int order, Index dofs);

}  // namespace warpfem::apps
