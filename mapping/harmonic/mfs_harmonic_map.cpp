#include "mapping/harmonic/mfs_harmonic_map.hpp"

#include <Eigen/QR>
#include <cmath>

#include "core/error.hpp"

namespace warpfem::mapping {
namespace {

Point<2> outward(const Polygon& P, Index i) {
  const Point<2> e = P.vertex(i + 1) - P.vertex(i);
  return Point<2>(e.y(), -e.x()).normalized();
}

std::shared_ptr<const MfsHarmonicCoordinates> solve(const Polygon& domain,
                                                    const std::vector<EdgeSpeed>& speeds_in,
                                                    const HarmonicOptions& o) {
  const Index n = domain.size();
  if (o.boundary_nodes < n)
    throw Error("mfs: " + std::to_string(o.boundary_nodes) + " sites are fewer than the " +
                    std::to_string(n) + " vertices of " + domain.name(),
                {.file = "", .key_path = "map.boundary_nodes", .hint = "use at least 4 sites per vertex"});
  require(o.mfs_oversampling >= 2, "mfs: mfs_oversampling must be at least 2");
  require(o.mfs_site_distance > 0, "mfs: mfs_site_distance must be positive");
  const std::vector<EdgeSpeed> speeds = speeds_for(domain, speeds_in);
  auto c = std::make_shared<MfsHarmonicCoordinates>();
  c->center = 0.5 * (domain.bbox_min() + domain.bbox_max());
  c->scale = diameter(domain);

  // sites
  const BoundaryNodes nodes = sample_boundary(domain, o.boundary_nodes);
  const Index m = nodes.size();
  for (Index j = 0; j < m; ++j) {
    const auto& at = nodes.at[static_cast<std::size_t>(j)];
    const Point<2> x = nodes.x[static_cast<std::size_t>(j)];
    Point<2> nrm = outward(domain, at.edge);
    if (at.t == 0) nrm = (nrm + outward(domain, at.edge - 1)).normalized();
    const Real h = 0.5 * ((nodes.x[static_cast<std::size_t>((j + 1) % m)] - x).norm() +
                          (nodes.x[static_cast<std::size_t>((j + m - 1) % m)] - x).norm());
    Real delta = o.mfs_site_distance * h;
    Point<2> s = x + delta * nrm;
    for (int k = 0; k < 30; ++k, delta *= 0.5, s = x + delta * nrm) {
      Real dist = 0;
      closest_boundary_point(domain, s, &dist);
      if (domain.side_of(s) < 0 && dist >= 0.5 * delta) break;
    }
    c->sites.push_back((s - c->center) / c->scale);
  }

  // least squares at k ≫ m boundary nodes
  const BoundaryNodes col = sample_boundary(domain, o.mfs_oversampling * m);
  const Index k = col.size();
  MatrixX A(k, m + 3), B(k, n);
  std::vector<Real> w(static_cast<std::size_t>(n));
  for (Index r = 0; r < k; ++r) {
    const Point<2> x = (col.x[static_cast<std::size_t>(r)] - c->center) / c->scale;
    for (Index i = 0; i < m; ++i) A(r, i) = std::log((x - c->sites[static_cast<std::size_t>(i)]).norm());
    A(r, m) = 1;
    A(r, m + 1) = x.x();
    A(r, m + 2) = x.y();
    boundary_weights(speeds, col.at[static_cast<std::size_t>(r)], w.data(), n);
    for (Index q = 0; q < n; ++q) B(r, q) = w[static_cast<std::size_t>(q)];
  }
  const VectorX colscale = A.colwise().norm().transpose().cwiseMax(1e-300).cwiseInverse();
  A = A * colscale.asDiagonal();
  c->weights = colscale.asDiagonal() * A.colPivHouseholderQr().solve(B);
  if (!c->weights.allFinite())
    throw Error(
        "mfs: the least-squares problem of " + domain.name() + " failed",
        {.file = "", .key_path = "map.boundary_nodes", .hint = "change the number of boundary nodes"});
  return c;
}

}  // namespace

MfsHarmonicMap::MfsHarmonicMap(const Polygon& domain, const Polygon& image,
                               const std::vector<EdgeSpeed>& speeds, const HarmonicOptions& options)
    : MfsHarmonicMap(solve(domain, speeds, options), domain, image, speeds) {}

MfsHarmonicMap::MfsHarmonicMap(std::shared_ptr<const MfsHarmonicCoordinates> coordinates,
                               const Polygon& domain, const Polygon& image,
                               const std::vector<EdgeSpeed>& speeds)
    : HarmonicMap(domain, image, speeds), coords_(std::move(coordinates)) {
  const Index m = static_cast<Index>(coords_->sites.size());
  const MatrixX Wc = coords_->weights * image_vertices();
  sx_.resize(m);
  sy_.resize(m);
  for (Index i = 0; i < m; ++i) {
    sx_(i) = coords_->sites[static_cast<std::size_t>(i)].x();
    sy_(i) = coords_->sites[static_cast<std::size_t>(i)].y();
  }
  w0_ = Wc.col(0).head(m);
  w1_ = Wc.col(1).head(m);
  affine_ = Wc.bottomRows(3);
}

void MfsHarmonicMap::eval_point(const Point<2>& x, Point<2>& phi, Matrix<2>* J) const {
  const Point<2> xs = (x - coords_->center) / coords_->scale;
  const Index m = sx_.size();
  Real p0 = 0, p1 = 0, j00 = 0, j01 = 0, j10 = 0, j11 = 0;
  for (Index i = 0; i < m; ++i) {
    const Real rx = xs.x() - sx_(i), ry = xs.y() - sy_(i);
    const Real r2 = rx * rx + ry * ry;
    const Real l = 0.5 * std::log(r2);
    p0 += w0_(i) * l;
    p1 += w1_(i) * l;
    if (J) {
      const Real inv = 1 / r2;
      j00 += w0_(i) * rx * inv;
      j01 += w0_(i) * ry * inv;
      j10 += w1_(i) * rx * inv;
      j11 += w1_(i) * ry * inv;
    }
  }
  phi = Point<2>(p0 + affine_(0, 0) + affine_(1, 0) * xs.x() + affine_(2, 0) * xs.y(),
                 p1 + affine_(0, 1) + affine_(1, 1) * xs.x() + affine_(2, 1) * xs.y());
  if (J)
    *J = (Matrix<2>() << j00 + affine_(1, 0), j01 + affine_(2, 0), j10 + affine_(1, 1), j11 + affine_(2, 1))
             .finished() /
         coords_->scale;
}

HarmonicMapPtr MfsHarmonicMap::with_image(const Polygon& image) const {
  return std::make_shared<const MfsHarmonicMap>(coords_, domain(), image, speeds());
}

std::vector<Point<2>> MfsHarmonicMap::sites() const {
  std::vector<Point<2>> s;
  for (const auto& p : coords_->sites) s.push_back(coords_->center + coords_->scale * p);
  return s;
}

}  // namespace warpfem::mapping
