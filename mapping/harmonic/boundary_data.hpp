#pragma once
// Boundary data of a harmonic map φ: Ω → Λ (thesis §5 and §5.4).
//
// ∂Ω is parametrized edge by edge: edge i joins vertex i and i+1, t ∈ [0, 1].
// The boundary condition sends (edge i, t) to (1 − s_i(t)) w_i + s_i(t) w_{i+1},
// with w the vertices of Λ and s_i the *speed* of edge i: s(t) = t (piecewise
// linear, the default), t² (quadratic, §5.4) or 1 − (1 − t)². Because the data
// is linear in w, φ = Σ_k w_k λ_k where λ_k is the harmonic function with the
// data of "vertex k = 1, all others 0" (a harmonic coordinate); every solver
// in this folder computes the λ_k once and reuses them for any Λ.

#include <optional>
#include <string>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/polygon.hpp"
#include "core/types.hpp"

namespace warpfem::mapping {

enum class EdgeSpeed { linear, quadratic, quadratic_reversed };

/// "linear" | "quadratic" | "quadratic_reversed"; throws warpfem::Error otherwise.
EdgeSpeed parse_edge_speed(const std::string& name);
std::string to_string(EdgeSpeed speed);

/// s(t) for t ∈ [0, 1]; s(0) = 0, s(1) = 1.
Real edge_speed(EdgeSpeed speed, Real t);

/// One speed per edge of `domain`: `speeds` itself, or all linear when empty.
/// Throws warpfem::Error if the count does not match.
std::vector<EdgeSpeed> speeds_for(const Polygon& domain, const std::vector<EdgeSpeed>& speeds);

/// A point of ∂Ω as (edge, parameter).
struct BoundaryPoint {
  Index edge = 0;
  Real t = 0;
};

/// Nodes on ∂Ω in counter-clockwise order, all vertices included; node j and
/// j+1 (cyclically) bound the j-th boundary element, which lies on one edge.
struct BoundaryNodes {
  std::vector<Point<2>> x;
  std::vector<BoundaryPoint> at;
  Index size() const { return static_cast<Index>(x.size()); }
};

/// About `count` nodes, spread over the edges proportionally to their length,
/// every edge split into at least one element.
BoundaryNodes sample_boundary(const Polygon& domain, Index count);

/// Every edge split into ceil(length / max_length) equal elements.
BoundaryNodes subdivide_boundary(const Polygon& domain, Real max_length);

/// Values of the n harmonic-coordinate boundary conditions at `p`: row k is the
/// weight of vertex k of Λ; only entries edge and edge+1 are non-zero.
void boundary_weights(const std::vector<EdgeSpeed>& speeds, const BoundaryPoint& p, Real* weights, Index n);

/// The boundary condition itself: (1 − s) w_e + s w_{e+1}.
Point<2> boundary_value(const Polygon& image, const std::vector<EdgeSpeed>& speeds, const BoundaryPoint& p);

/// Closest point of ∂Ω to `x` and its distance.
BoundaryPoint closest_boundary_point(const Polygon& domain, const Point<2>& x, Real* distance);

/// Per vertex of `mesh` (a mesh of `domain`): its closest point of ∂Ω if it is
/// a vertex of a boundary facet, nothing if it is interior.
std::vector<std::optional<BoundaryPoint>> boundary_points(const Mesh<2>& mesh, const Polygon& domain);

/// Point of ∂Ω at `p`.
Point<2> boundary_position(const Polygon& domain, const BoundaryPoint& p);

/// Length of the bounding-box diagonal (the length scale of all tolerances here).
Real diameter(const Polygon& polygon);

}  // namespace warpfem::mapping
