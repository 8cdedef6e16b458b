#pragma once
// P1 finite element approximation of a harmonic map (thesis §5.1.1): the
// harmonic coordinates λ_k at the vertices of a constrained Delaunay mesh of Ω,
// φ linear on each triangle. Evaluation locates the point in the mesh; J_φ is
// constant per triangle.

#include <memory>

#include "core/mesh/cell_locator.hpp"
#include "core/mesh/mesh.hpp"
#include "mapping/harmonic/harmonic_map.hpp"

namespace warpfem::mapping {

/// What the solve produces and every image Λ shares. Not copyable: the
/// locator refers to the mesh beside it.
struct FemHarmonicCoordinates {
  FemHarmonicCoordinates(Mesh<2> mesh, MatrixX lambda);
  FemHarmonicCoordinates(const FemHarmonicCoordinates&) = delete;
  FemHarmonicCoordinates& operator=(const FemHarmonicCoordinates&) = delete;

  Mesh<2> mesh;         ///< the auxiliary mesh of Ω (p1_laplace.hpp)
  MatrixX lambda;       ///< nv x n
  CellLocator locator;  ///< over `mesh`
};

class FemHarmonicMap final : public HarmonicMap {
 public:
  /// Meshes Ω with edges ≤ max_edge_length and solves the n Laplace problems.
  FemHarmonicMap(const Polygon& domain, const Polygon& image, const std::vector<EdgeSpeed>& speeds,
                 Real max_edge_length);
  FemHarmonicMap(std::shared_ptr<const FemHarmonicCoordinates> coordinates, const Polygon& domain,
                 const Polygon& image, const std::vector<EdgeSpeed>& speeds);

  HarmonicMethod method() const override { return HarmonicMethod::fem; }
  void eval_point(const Point<2>& x, Point<2>& phi, Matrix<2>* J) const override;
  HarmonicMapPtr with_image(const Polygon& image) const override;
  bool is_piecewise_linear() const override { return true; }

  const Mesh<2>& mesh() const { return coords_->mesh; }
  /// nv x 2: φ at the mesh vertices.
  const Points<2>& vertex_images() const { return images_; }
  /// J_φ on triangle t.
  Matrix<2> triangle_jacobian(Index t) const { return jacobian_at<2>(J_, t); }

 private:
  std::shared_ptr<const FemHarmonicCoordinates> coords_;
  Points<2> images_;
  Jacobians<2> J_;  ///< per triangle
};

/// J of the linear map sending triangle (p0, p1, p2) to (q0, q1, q2).
Matrix<2> affine_jacobian(const Point<2>& p0, const Point<2>& p1, const Point<2>& p2, const Point<2>& q0,
                          const Point<2>& q1, const Point<2>& q2);

}  // namespace warpfem::mapping
