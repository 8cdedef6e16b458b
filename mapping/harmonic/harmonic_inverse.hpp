#pragma once
// The inverse of a harmonic map φ: Ω → Λ (thesis §5.2).
//
// A triangle mesh of Ω is pushed through φ; locating z in the image mesh gives
// the piecewise-linear inverse (exact for fem, whose φ is linear on that very
// mesh). For the smooth bem/mfs maps this is only the seed of a damped Newton
// iteration on φ(y) = z that stays inside the triangle of Ω whose image holds z,
// walking into the neighbouring triangle when a step leaves through an interior
// edge and sliding along ∂Ω when it leaves through a boundary edge — so φ is
// never evaluated outside Ω.

#include <memory>

#include "core/mesh/cell_locator.hpp"
#include "core/mesh/mesh.hpp"
#include "mapping/harmonic/harmonic_map.hpp"

namespace warpfem::mapping {

class HarmonicInverse {
 public:
  /// seed_max_edge_length: edge length of the seed mesh of Ω (ignored for fem,
  /// which uses its own mesh).
  HarmonicInverse(HarmonicMapPtr phi, Real seed_max_edge_length);
  HarmonicInverse(const HarmonicInverse&) = delete;  // the locator refers to images_
  HarmonicInverse& operator=(const HarmonicInverse&) = delete;

  struct Result {
    Real residual = 0;  ///< |φ(y) − z| reached (fem: distance of z from the located triangle's image)
    int iterations = 0;
  };

  /// y = φ⁻¹(z) and, if J is given, J_φ(y).
  Result apply(const Point<2>& z, Point<2>& y, Matrix<2>* J) const;

  const HarmonicMap& map() const { return *phi_; }
  /// Newton stops at |φ(y) − z| ≤ tolerance (default 1e-13 · diameter(Λ)).
  Real tolerance() const { return tol_; }

 private:
  HarmonicMapPtr phi_;
  std::shared_ptr<const Mesh<2>> mesh_;   ///< of Ω
  Points<2> images_;                      ///< φ at the vertices of mesh_
  IndexTable neighbours_;                 ///< of mesh_ (simplex_neighbours), for the Newton walk
  std::unique_ptr<CellLocator> locator_;  ///< over the image mesh (images_, mesh_->cells)
  Real tol_ = 0;
};

}  // namespace warpfem::mapping
