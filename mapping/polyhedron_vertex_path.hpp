#pragma once
// Vertex paths ψ_i: [0,1] → R³ between two polyhedra with the same triangulation
// (thesis §3.2, §4.4.2); they define the intermediate polyhedra Ω_t of a composite map.
//
//  * linear:    ψ_i(t) = (1 − t) v0_i + t v1_i. A rotation by θ shrinks the cage by
//               cos(θ/2) across the axis half-way (a half turn crushes it flat).
//  * intrinsic: per-triangle affine interpolation with the rotation in log space
//               (Alexa, Cohen-Or & Levin 2000; Sumner & Popović 2004), the 3D
//               counterpart of the 2D intrinsic path. For each triangle the affine
//               map A_T taking source to target triangle, completed in the normal
//               direction by n/√|n| (n = e1 × e2, so det A_T > 0), is split by the
//               polar decomposition A_T = R_T S_T. A global rotation G (the rotation
//               of the best linear fit of the centred vertex sets, Kabsch) is taken
//               out first, so that each face's rotation is interpolated relative to
//               it: R_T(t) = exp(t log(R_T Gᵀ)) exp(t log G), S_T(t) = (1 − t) I + t S_T
//               (symmetric positive definite for every t: no triangle shrinks to a
//               segment). The vertices at t are the least-squares fit of the edge
//               vectors, min Σ_T Σ_{e ∈ T} |ψ_b − ψ_a − A_T(t)(v0_b − v0_a)|² / |v0_b − v0_a|²,
//               a graph Laplacian solve (factored once) whose translation is fixed by
//               moving the vertex centroid linearly. A rigid motion of the source is
//               followed rigidly (every intermediate cage is congruent to the source),
//               and the path commutes with a similarity transformation of both cages.
//               Faces whose own rotation relative to G approaches a half turn have an
//               ambiguous logarithm; then neighbouring faces may disagree and the
//               intermediate cage may self-intersect, which build_polyhedron_composite
//               reports naming t.
// Both reproduce the source at t = 0 and the target at t = 1 exactly (bit for bit).

#include <memory>
#include <vector>

#include "core/polyhedron.hpp"
#include "mapping/vertex_path.hpp"

namespace warpfem::mapping {

class PolyhedronVertexPath {
 public:
  /// Source and target must share the triangulation (throws warpfem::Error).
  PolyhedronVertexPath(const Polyhedron& source, const Polyhedron& target,
                       VertexPathType type = VertexPathType::linear);

  /// Vertices ψ_i(t), t in [0, 1]; not validated.
  std::vector<Point<3>> vertices_at(Real t) const;

  /// The same path run backwards: ψ'(t) = ψ(1 − t), from the target to the source.
  PolyhedronVertexPath reversed() const;

  VertexPathType type() const { return type_; }
  const std::vector<Point<3>>& source() const { return reversed_ ? v1_ : v0_; }
  const std::vector<Point<3>>& target() const { return reversed_ ? v0_ : v1_; }
  const std::vector<Polyhedron::Triangle>& triangles() const { return triangles_; }

 private:
  struct Intrinsic;
  std::vector<Point<3>> forward_at(Real t) const;

  std::vector<Point<3>> v0_, v1_;
  std::vector<Polyhedron::Triangle> triangles_;
  VertexPathType type_;
  bool reversed_ = false;
  std::shared_ptr<const Intrinsic> intrinsic_;  ///< shared by reversed copies
};

}  // namespace warpfem::mapping
