#pragma once
// Meshes and problems shared by the multigrid tests: the L-shape of the
// shipped examples, triangles or quadrilaterals, and a Poisson problem with
// Dirichlet data on part of the boundary.

#include <cmath>
#include <optional>

#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/polygon.hpp"
#include "fem/physics/poisson.hpp"

namespace warpfem::multigrid::test {

inline Polygon l_shape() {
  return Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L-shape");
}

/// Coarse mesh of the L-shape: Delaunay triangles, or those split into quadrilaterals.
inline warpfem::Mesh<2> coarse_l_shape(warpfem::CellType type, double h) {
  warpfem::Mesh<2> m = warpfem::mesh_polygon(l_shape(), {.max_edge_length = h});
  return type == warpfem::CellType::triangle ? m : warpfem::split_into_quadrilaterals(m);
}

/// −Δu = 1 + xy, u = x on edges 0, 1, 2 (re-entrant corner included), natural Neumann elsewhere.
/// Boundary parts are selected per node on `polygon` (as apps/ does), by facet tag if it is empty.
inline fem::PoissonData<2> mixed_problem(std::optional<Polygon> polygon = l_shape()) {
  fem::PoissonData<2> data;
  data.boundary_polygon = std::move(polygon);
  data.source = [](const Point<2>& x, double) { return 1.0 + x.x() * x.y(); };
  data.dirichlet.push_back({.edges = {0, 1, 2}, .value = [](const Point<2>& x, double) { return x.x(); }});
  return data;
}

/// −Δu = 1, u = 0 on the whole boundary (the gear studies).
inline fem::PoissonData<2> unit_source_zero_dirichlet() {
  fem::PoissonData<2> data;
  data.source = fem::ConstantFunction{1.0};
  data.dirichlet.push_back({.edges = {}, .value = [](const Point<2>&, double) { return 0.0; }});
  return data;
}

}  // namespace warpfem::multigrid::test
