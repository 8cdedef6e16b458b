#pragma once
// Mean value coordinates of a closed triangulated polyhedron (Floater, Kós and
// Reimers 2005; Ju, Schaefer and Warren 2005). For a point x and a triangle T
// with s_a = p_a − x, N_e = s_a × s_b for its edges e = (a, b), β_e the angle
// between s_a and s_b, and D = det(s_1, s_2, s_3), the mean vector of T seen
// from x is m_T = ½ Σ_e β_e N_e / |N_e| and T contributes
//   w_i += m_T · N_i / D,      N_i = the N of the edge opposite vertex i,
// to the weight of each of its vertices; φ_i = w_i / Σ_j w_j. They reproduce
// linear functions, are the linear interpolant on every triangle and the
// Kronecker delta at the vertices, and are smooth inside.
//
// Batched over points (N x 3, SoA) with a vectorized kernel and analytic
// gradients. Points near the surface, near a vertex, or close to the edge line
// of some triangle are re-evaluated by a robust formula with weights scaled by
// the distance to the surface. For a triangle whose plane passes (nearly)
// through x its contribution is taken in a form with the factor h (distance to
// the plane) taken out exactly, so that the contribution h·F(x) and its
// gradient F ∇h + h ∇F keep full accuracy as h → 0 (skipping the triangle
// would be right for the value but wrong for the gradient); the batched
// functions do this for that triangle alone and keep the vectorized result
// for the others. All tolerances
// are relative to local lengths, so the coordinates are invariant under
// similarity transforms.

#include <vector>

#include "core/polyhedron.hpp"
#include "core/types.hpp"

namespace warpfem::mapping {

/// A polyhedron's vertices and triangles as contiguous arrays (the form the
/// kernels loop over). Coordinates are stored normalized, (p − center) / scale
/// with scale the bounding-box diagonal, which makes every tolerance relative.
struct PolyhedronArrays {
  std::vector<Real> x, y, z;   ///< normalized vertex coordinates
  std::vector<int> a, b, c;    ///< vertex indices of each triangle (outward)
  std::vector<Real> two_area;  ///< |(p_b − p_a) × (p_c − p_a)| of each triangle (normalized)
  /// Each edge once (edge_a < edge_b), and per triangle the indices of its edges
  /// opposite a, b and c (3 per triangle): the kernels compute the angle terms
  /// of an edge once for the two triangles that share it.
  std::vector<int> edge_a, edge_b, triangle_edges;
  /// The order the kernels visit the triangles in (breadth first over shared
  /// edges), and the edges computed before each: before the i-th triangle of
  /// `order`, scheduled_edges[edge_first[i] .. edge_first[i + 1]). Each edge's
  /// terms live in a slot (edge_slot) that is reused once its last triangle is
  /// done, so that only the edges open at any time (slot_count: 19 of 144 on
  /// a 96-triangle sphere) take scratch memory.
  std::vector<int> order, edge_first, scheduled_edges, edge_slot;
  int slot_count = 0;
  Point<3> center = Point<3>::Zero();
  Real scale = 1;

  PolyhedronArrays() = default;
  explicit PolyhedronArrays(const Polyhedron& polyhedron);
  PolyhedronArrays(const std::vector<Point<3>>& vertices, const std::vector<Polyhedron::Triangle>& triangles);
  Index size() const { return static_cast<Index>(x.size()); }
  Index triangle_count() const { return static_cast<Index>(a.size()); }

 private:
  void schedule_edges();
};

/// φ (N x n): column i holds φ_i at every point.
void mean_value_coordinates(const PolyhedronArrays& polyhedron, const Points<3>& x, MatrixX& phi);

/// φ and ∇φ (each N x n).
void mean_value_coordinates(const PolyhedronArrays& polyhedron, const Points<3>& x, MatrixX& phi,
                            MatrixX& dphi_dx, MatrixX& dphi_dy, MatrixX& dphi_dz);

/// The mean value combination of vertex values (n x 3, row i at vertex i):
/// g(x) = Σ_i φ_i(x) values_i at every point, and if J is given its Jacobian
/// Σ_i values_i ∇φ_i(x)ᵀ (J(p, 3 r + c) = ∂g_r/∂x_c). The same numbers as φ ·
/// values and ∇φ · values from mean_value_coordinates, without the N x n
/// coordinate matrices: one step of a mean value map.
void mean_value_combination(const PolyhedronArrays& polyhedron, const Points<3>& x, const MatrixX& values,
                            Points<3>& g, Jacobians<3>* J = nullptr);

/// Robust evaluation at a single point (the path of the batched functions for
/// points near the surface or near a triangle's plane, exposed for tests).
/// Writes n values to phi and, if dx is not null, n gradient components to
/// each of dx, dy, dz. On a vertex φ is the Kronecker delta and on an edge the
/// linear interpolant; the gradient there (where φ is not differentiable) is
/// the one just inside.
void mean_value_coordinates_at(const PolyhedronArrays& polyhedron, const Point<3>& x, Real* phi, Real* dx,
                               Real* dy, Real* dz);

}  // namespace warpfem::mapping
