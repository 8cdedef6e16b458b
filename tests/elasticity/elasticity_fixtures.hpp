#pragma once
// Small meshes, maps and helpers shared by the elasticity tests.

#include <cmath>
#include <type_traits>

#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/petsc/check.hpp"
#include "fem/physics/elasticity/hyperelastic_operator.hpp"
#include "mapping/make_map.hpp"

namespace warpfem::test {

inline Polygon rectangle(double w, double h) {
  return Polygon({Point<2>(0, 0), Point<2>(w, 0), Point<2>(w, h), Point<2>(0, h)}, "rectangle");
}

/// Structured triangle or quadrilateral mesh of [0, w] x [0, h], refined `refinements` times.
inline warpfem::Mesh<2> block_mesh(double w, double h, int nx, int ny, warpfem::CellType type,
                                   int refinements = 0) {
  warpfem::Mesh<2> mesh = warpfem::structured_mesh(rectangle(w, h), nx, ny, type);
  for (int r = 0; r < refinements; ++r) mesh = warpfem::refine_uniformly(mesh).mesh;
  return mesh;
}

/// A smooth non-affine warp of the unit square onto a quadrilateral-ish domain (barycentric map).
inline mapping::MapPtr<2> warped_square_map() {
  mapping::MapSpec spec;
  spec.type = "barycentric";
  spec.source = rectangle(1, 1);
  spec.target =
      Polygon({Point<2>(0, 0), Point<2>(1.1, 0.1), Point<2>(1.2, 1.0), Point<2>(-0.1, 0.9)}, "target");
  return mapping::make_map(spec);
}

inline mapping::MapPtr<2> identity_map() {
  return std::make_shared<mapping::IdentityMap<2>>();
}

/// Global vector values as an Eigen vector (owned entries gathered to every rank).
template <int dim>
VectorX to_eigen(const fem::VectorSpace<dim>& space, Vec v) {
  return space.gather_all(v);
}

/// L2 norm over the warped domain of u_h - u_exact.
template <int dim>
double l2_error(const fem::HyperelasticOperator<dim>& op, Vec u,
                const std::type_identity_t<fem::VectorFunction<dim>>& exact) {
  return op.l2_error(u, exact);
}

}  // namespace warpfem::test
