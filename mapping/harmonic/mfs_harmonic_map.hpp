#pragma once
// Method of fundamental solutions (thesis §5.1.3): each harmonic coordinate is
//   λ_k(x) = Σ_i w_ik log|x − s_i| + a_k + b_k·x
// with m sites s_i outside Ω, placed along the outward (vertex-bisector) normal
// of m boundary nodes at mfs_site_distance times the local node spacing
// (Martin et al. 2008; pulled closer where that would land inside Ω or too close
// to another edge). Weights and the affine part minimize the squared boundary
// error at k = mfs_oversampling · m nodes (column-scaled Householder QR).
// Affine maps are reproduced exactly; evaluation costs O(m) per point.

#include <memory>

#include "mapping/harmonic/harmonic_map.hpp"

namespace warpfem::mapping {

struct MfsHarmonicCoordinates {
  Point<2> center;
  Real scale = 1;               ///< x̂ = (x − center) / scale
  std::vector<Point<2>> sites;  ///< scaled
  MatrixX weights;              ///< (m + 3) x n: site weights, then constant, x̂, ŷ
};

class MfsHarmonicMap final : public HarmonicMap {
 public:
  MfsHarmonicMap(const Polygon& domain, const Polygon& image, const std::vector<EdgeSpeed>& speeds,
                 const HarmonicOptions& options);
  MfsHarmonicMap(std::shared_ptr<const MfsHarmonicCoordinates> coordinates, const Polygon& domain,
                 const Polygon& image, const std::vector<EdgeSpeed>& speeds);

  HarmonicMethod method() const override { return HarmonicMethod::mfs; }
  void eval_point(const Point<2>& x, Point<2>& phi, Matrix<2>* J) const override;
  HarmonicMapPtr with_image(const Polygon& image) const override;
  /// Sites in Ω's frame.
  std::vector<Point<2>> sites() const;

 private:
  std::shared_ptr<const MfsHarmonicCoordinates> coords_;
  VectorX sx_, sy_, w0_, w1_;  ///< sites and weights combined with Λ
  Eigen::Matrix<Real, 3, 2> affine_;
};

}  // namespace warpfem::mapping
