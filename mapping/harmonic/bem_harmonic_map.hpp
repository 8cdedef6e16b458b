#pragma once
// Boundary element approximation of a harmonic map (thesis §5.1.2, eq. 5.6).
// With G_x(y) = −log|x − y| / 2π and n the outward normal,
//   ω(x) φ(x) = ∫_∂Ω G_x ∂φ/∂n − ∫_∂Ω φ ∂G_x/∂n,   ω = 1 inside, angle/2π on ∂Ω.
// φ and ∂φ/∂n are piecewise linear on m boundary elements; collocation at the
// nodes gives a dense system for ∂φ/∂n (solved once for all harmonic
// coordinates). ∂φ/∂n may jump at convex corners: there φ is C¹, so its two
// values follow from the tangential derivatives of the data (double nodes);
// elsewhere, including reflex corners, ∂φ/∂n is continuous and unknown. The free term ω(x_j) is taken as −Σ_i
// H_ji so constants are reproduced exactly. Integrals use Gauss–Legendre panels, bisected toward x until each
// panel is no closer to x than its length; the log-singular self-integrals are done analytically. Evaluation
// at x costs O(m · points) and J_φ is analytic; points within snap distance of ∂Ω take the boundary data.
// J_φ is the gradient of the representation at x itself, so φ and J_φ describe
// the same map: next to ∂Ω it carries the log|dist| singularities of the kinks
// of the hat density ∂φ/∂n, which the fold checks must see. Only on ∂Ω (within
// snap distance), where it is singular, it is the limit from just inside.
// Everything is computed in coordinates scaled to a unit bounding-box diagonal,
// which keeps the single-layer matrix away from its capacity-1 singularity.

#include <memory>

#include "core/mesh/quadrature.hpp"
#include "mapping/harmonic/harmonic_map.hpp"

namespace warpfem::mapping {

struct BemHarmonicCoordinates {
  Point<2> center;
  Real scale = 1;                    ///< x̂ = (x − center) / scale
  BoundaryNodes nodes;               ///< in scaled coordinates (at[] refers to Ω's edges)
  MatrixX c;                         ///< m x n: values of λ_k at the nodes
  MatrixX d_start, d_end;            ///< m x n: ∂λ_k/∂n at the start and end of each element (scaled)
  QuadratureRule<1> rule;            ///< Gauss–Legendre on [0, 1]
  Real snap = 0;                     ///< snap distance, scaled
  std::vector<Real> element_length;  ///< per edge of Ω, scaled
};

class BemHarmonicMap final : public HarmonicMap {
 public:
  BemHarmonicMap(const Polygon& domain, const Polygon& image, const std::vector<EdgeSpeed>& speeds,
                 const HarmonicOptions& options);
  BemHarmonicMap(std::shared_ptr<const BemHarmonicCoordinates> coordinates, const Polygon& domain,
                 const Polygon& image, const std::vector<EdgeSpeed>& speeds);

  HarmonicMethod method() const override { return HarmonicMethod::bem; }
  void eval_point(const Point<2>& x, Point<2>& phi, Matrix<2>* J) const override;
  HarmonicMapPtr with_image(const Polygon& image) const override;
  Index boundary_nodes() const { return coords_->nodes.size(); }

 private:
  void representation(const Point<2>& xs, Point<2>& phi, Matrix<2>* J) const;  // scaled x, no snapping

  std::shared_ptr<const BemHarmonicCoordinates> coords_;
  Eigen::Matrix<Real, Eigen::Dynamic, 2> C_, Ds_, De_;  ///< m x 2: c, d_start, d_end combined with Λ
  // per Gauss point of every element: position, normal, weight·length, c and d;
  // `near_` with the full rule (elements ≥ 1 length away), `far_` with 4 points (≥ 4 lengths)
  struct QuadratureTable {
    Index per_element = 0;
    VectorX x, y, nx, ny, w, c0, c1, d0, d1;
  };
  void fill_table(QuadratureTable& table, const QuadratureRule<1>& rule) const;
  QuadratureTable near_, far_;
};

}  // namespace warpfem::mapping
