#pragma once
// Vertex paths ψ_i: [0,1] → R², ψ_i(0) = source vertex i, ψ_i(1) = target vertex i
// (thesis §3.1, §4.2). They define the intermediate polygons Ω_t of a composite map.
//
//  * linear:    ψ_i(t) = (1 − t) v0_i + t v1_i. Simple, but depends on position and
//               tends to self-intersect under rotations.
//  * intrinsic: Sederberg, Gao, Wang & Mu (1993): interpolate edge lengths L_i and
//               exterior (turning) angles α_i linearly, and the direction of edge 0
//               (taking the rotation of less than π). The polygon rebuilt from them
//               is generally open; the closing step changes the lengths as little
//               as possible, min Σ (ΔL_i / S_i)² subject to Σ (L_i + ΔL_i) u_i = 0
//               (u_i the edge directions, S_i = max(|L0_i − L1_i|, tol)), whose
//               closed-form solution is ΔL_i = S_i² (μ · u_i) with the 2x2 system
//               (Σ S_i² u_i u_iᵀ) μ = −Σ L_i u_i. Finally the vertex centroid is
//               interpolated linearly. Invariant under similarity transformations.
// Both reproduce the source at t = 0 and the target at t = 1 exactly (bit for bit).

#include <string>
#include <vector>

#include "core/polygon.hpp"

namespace warpfem::mapping {

enum class VertexPathType { linear, intrinsic };

/// "linear" | "intrinsic"; throws warpfem::Error otherwise.
VertexPathType parse_vertex_path(const std::string& name);
std::string to_string(VertexPathType type);

class VertexPath {
 public:
  /// Both polygons must be valid and have the same vertex count (throws warpfem::Error).
  VertexPath(Polygon source, Polygon target, VertexPathType type = VertexPathType::linear);

  /// Vertices ψ_i(t), t in [0, 1]; not validated.
  std::vector<Point<2>> vertices_at(Real t) const;

  /// The intermediate polygon Ω_t, validated (simple, counter-clockwise). Throws
  /// warpfem::Error naming t if the path produces an invalid polygon there.
  Polygon polygon_at(Real t) const;

  VertexPathType type() const { return type_; }
  const Polygon& source() const { return source_; }
  const Polygon& target() const { return target_; }
  Index size() const { return source_.size(); }

 private:
  Polygon source_, target_;
  VertexPathType type_;
  // intrinsic data
  std::vector<Real> length0_, length1_, turn0_, turn1_, weight_;
  Real theta0_ = 0, theta1_ = 0;
  Point<2> centroid0_, centroid1_;
};

}  // namespace warpfem::mapping
