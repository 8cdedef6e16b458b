#pragma once
// Composite harmonic maps between polyhedra (thesis §5.5): f = φ1⁻¹ ∘ φ0
// with φ0: Ω0 → Λ and φ1: Ω1 → Λ harmonic onto a convex intermediate
// polyhedron Λ with the cage's triangulation, each with the piecewise-linear
// boundary map of the cage triangles onto Λ's. Λ is the source itself when
// the source is convex (then φ0 is the identity and f = φ1⁻¹, exact for
// affine targets), otherwise its spherical embedding (spherical_intermediate.hpp). Both are P1 finite element
// solutions on TetGen meshes, so φ0, φ1 and f are only piecewise linear
// (C0, J_f constant on each overlap of a cell of φ0 and the preimage of a
// cell of φ1), like the 2D FEM variant.
//
// In 3D no Radó–Kneser–Choquet theorem makes a harmonic map onto a convex
// domain bijective, so every map is checked when built: every cell of both
// meshes must keep det J_φ > 0 (a piecewise-linear map that is orientation-
// preserving on every cell and a homeomorphism of the boundary is a
// bijection), otherwise it is refused naming the cell.

#include <memory>
#include <string>

#include "core/mesh/mesh.hpp"
#include "core/mesh/tetgen_mesher.hpp"
#include "core/polyhedron.hpp"
#include "mapping/harmonic/tet_locator.hpp"
#include "mapping/map.hpp"

namespace warpfem::mapping {

/// One P1 harmonic map φ: Ω → Λ on a tetrahedral mesh of Ω, affine on each
/// cell, with locators on the mesh (for φ) and on its image (for φ⁻¹). Not
/// copyable: the locators refer to the members beside them.
class TetHarmonicMap {
 public:
  /// Meshes `domain` with TetGen (its triangles may be split, every boundary
  /// vertex gets the linear image on its triangle of `image`'s) and solves
  /// the three Laplace problems with one factorisation. Interior edges
  /// between two surface vertices are split first (a free midpoint): the
  /// boundary data alone would fix their image, a chord of ∂Λ.
  TetHarmonicMap(const Polyhedron& domain, const Polyhedron& image, const TetrahedralMeshOptions& mesh);
  TetHarmonicMap(const TetHarmonicMap&) = delete;
  TetHarmonicMap& operator=(const TetHarmonicMap&) = delete;

  const Mesh<3>& mesh() const { return mesh_; }
  const Points<3>& image_vertices() const { return image_; }
  /// J_φ on cell c and its determinant relative to |Λ| / |Ω| (1 for a
  /// similarity; +∞ for the flat cells TetGen may leave on planar parts of
  /// the surface, which no point is located in).
  const Matrix<3>& jacobian(Index c) const { return jacobians_[static_cast<std::size_t>(c)]; }
  Real relative_det(Index c) const { return relative_det_(c); }
  const VectorX& relative_dets() const { return relative_det_; }

  /// φ(x) and its cell; returns the least barycentric coordinate of x in
  /// that cell (≥ 0 inside Ω, negative outside; the barycentric coordinates
  /// are clamped to [0, 1] before they are used).
  Real forward(const Point<3>& x, Point<3>& y, Index& cell) const;
  /// The same for φ⁻¹(y): the cell of the image mesh containing y. Of
  /// several (y on a shared face) the one containing `towards`, a point a
  /// little way from y, if that cell contains y up to round-off: a
  /// composition then takes J from one side of the face in both maps.
  Real backward(const Point<3>& y, const Point<3>& towards, Point<3>& x, Index& cell) const;

 private:
  Mesh<3> mesh_;
  Points<3> image_;
  std::vector<Matrix<3>> jacobians_;
  VectorX relative_det_;
  Real scale_ = 1;
  std::unique_ptr<TetLocator> domain_locator_, image_locator_;
  void update_cell(Index c);
};

class PolyhedronHarmonicMap final : public Map<3> {
 public:
  PolyhedronHarmonicMap(std::shared_ptr<const TetHarmonicMap> phi0,
                        std::shared_ptr<const TetHarmonicMap> phi1, Polyhedron intermediate);

  /// Points outside Ω0 (beyond round-off) get NaN values and Jacobians.
  void eval(const Points<3>& x0, Points<3>& x) const override;
  void jacobian(const Points<3>& x0, Jacobians<3>& J) const override;
  void eval_with_jacobian(const Points<3>& x0, Points<3>& x, Jacobians<3>& J) const override;
  /// residual(p) = |φ1(f(x0)) − φ0(x0)|, the distance by which φ0(x0) misses
  /// the image mesh of φ1 (round-off for a checked map).
  void eval_with_residual(const Points<3>& x0, Points<3>& x, Jacobians<3>& J,
                          VectorX& residual) const override;
  Real inverse_tolerance() const override { return 1e-9; }
  std::string describe() const override;

  /// f⁻¹ = φ0⁻¹ ∘ φ1 (point location and the affine inverse on one cell,
  /// exact up to round-off); residual(p) = |φ0(x(p)) − φ1(y(p))|, NaN x
  /// where y(p) lies outside Ω1.
  void inverse(const Points<3>& y, Points<3>& x, VectorX& residual) const;

  /// Null when φ0 is the identity.
  const TetHarmonicMap* phi0() const { return phi0_.get(); }
  const TetHarmonicMap& phi1() const { return *phi1_; }
  const Polyhedron& intermediate() const { return intermediate_; }

 private:
  void run(const TetHarmonicMap* from, const TetHarmonicMap* to, const Points<3>& x0, Points<3>* x,
           Jacobians<3>* J, VectorX* residual) const;
  std::shared_ptr<const TetHarmonicMap> phi0_, phi1_;
  Polyhedron intermediate_;
  Point<3> intermediate_centroid_;
};

struct PolyhedronHarmonicOptions {
  Real max_volume = 0;     ///< TetGen volume bound in Ω0 (Ω1's is scaled by |Ω1|/|Ω0|); 0: |Ω0| / 5000
  Real quality_ratio = 2;  ///< TetGen radius-edge bound of both meshes
  /// TetGen's dihedral angle bound in degrees: P1 harmonic maps invert
  /// slivers next to the boundary, so the meshes avoid them.
  Real min_dihedral_angle = 18;
  bool spherical = false;      ///< Λ on the sphere even when the source is convex
  Real min_det = 1e-8;         ///< every cell's det J_φ relative to |Λ| / |Ω| must exceed this
  int relaxation_steps = 512;  ///< spherical_intermediate()
};

/// Builds Λ, φ0 and φ1 and refuses (warpfem::Error naming the polyhedron,
/// the cell, where it lies and the min det, with a fix) when a cell of
/// either map is inverted or nearly flat.
std::shared_ptr<const PolyhedronHarmonicMap> build_polyhedron_harmonic(
    const Polyhedron& source, const Polyhedron& target, const PolyhedronHarmonicOptions& options = {});

}  // namespace warpfem::mapping
