#include "mapping/harmonic/fem_harmonic_map.hpp"

#include <Eigen/LU>

#include "mapping/harmonic/p1_laplace.hpp"

namespace warpfem::mapping {
namespace {

std::shared_ptr<const FemHarmonicCoordinates> solve(const Polygon& domain,
                                                    const std::vector<EdgeSpeed>& speeds, Real h) {
  Mesh<2> mesh = auxiliary_mesh(domain, h);
  MatrixX lambda = p1_harmonic_coordinates(mesh, domain, speeds_for(domain, speeds), domain.size());
  return std::make_shared<const FemHarmonicCoordinates>(std::move(mesh), std::move(lambda));
}

Point<2> row(const Points<2>& P, Index i) {
  return P.row(i).transpose();
}

}  // namespace

FemHarmonicCoordinates::FemHarmonicCoordinates(Mesh<2> mesh_in, MatrixX lambda_in)
    : mesh(std::move(mesh_in)), lambda(std::move(lambda_in)), locator(mesh) {}

Matrix<2> affine_jacobian(const Point<2>& p0, const Point<2>& p1, const Point<2>& p2, const Point<2>& q0,
                          const Point<2>& q1, const Point<2>& q2) {
  Matrix<2> E, F;
  E << p1 - p0, p2 - p0;
  F << q1 - q0, q2 - q0;
  return F * E.inverse();
}

FemHarmonicMap::FemHarmonicMap(const Polygon& domain, const Polygon& image,
                               const std::vector<EdgeSpeed>& speeds, Real max_edge_length)
    : FemHarmonicMap(solve(domain, speeds, max_edge_length), domain, image, speeds) {}

FemHarmonicMap::FemHarmonicMap(std::shared_ptr<const FemHarmonicCoordinates> coordinates,
                               const Polygon& domain, const Polygon& image,
                               const std::vector<EdgeSpeed>& speeds)
    : HarmonicMap(domain, image, speeds), coords_(std::move(coordinates)) {
  images_ = coords_->lambda * image_vertices();
  const Mesh<2>& m = coords_->mesh;
  J_.resize(m.num_cells(), 4);
  for (Index t = 0; t < m.num_cells(); ++t) {
    const auto T = m.cells.row(t);
    set_jacobian_at<2>(J_, t,
                       affine_jacobian(row(m.vertices, T[0]), row(m.vertices, T[1]), row(m.vertices, T[2]),
                                       row(images_, T[0]), row(images_, T[1]), row(images_, T[2])));
  }
}

void FemHarmonicMap::eval_point(const Point<2>& x, Point<2>& phi, Matrix<2>* J) const {
  const CellLocator::Nearest hit = coords_->locator.nearest(x);
  const auto T = coords_->mesh.cells.row(hit.cell);
  phi = hit.barycentric[0] * row(images_, T[0]) + hit.barycentric[1] * row(images_, T[1]) +
        hit.barycentric[2] * row(images_, T[2]);
  if (J) *J = triangle_jacobian(hit.cell);
}

HarmonicMapPtr FemHarmonicMap::with_image(const Polygon& image) const {
  return std::make_shared<const FemHarmonicMap>(coords_, domain(), image, speeds());
}

}  // namespace warpfem::mapping
