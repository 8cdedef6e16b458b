#include "core/mesh/cell_locator.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace warpfem {

CellLocator::CellLocator(const Mesh<2>& mesh) : mesh_(mesh) {
  mesh.require_whole("CellLocator");
  const Index nc = mesh.num_cells();
  lo_ = mesh.vertices.colwise().minCoeff().transpose();
  const Point<2> hi = mesh.vertices.colwise().maxCoeff().transpose();
  const Point<2> extent = (hi - lo_).cwiseMax(1e-300);
  // About one cell per bucket.
  const double buckets = std::max<double>(1.0, static_cast<double>(nc));
  const double aspect = extent.x() / extent.y();
  nx_ = std::max(1, static_cast<int>(std::sqrt(buckets * aspect)));
  ny_ = std::max(1, static_cast<int>(buckets / nx_));
  cell_size_ = Point<2>(extent.x() / nx_, extent.y() / ny_);
  const int nv = vertices_per_cell(mesh.cell_type);
  std::vector<std::array<int, 4>> range(static_cast<std::size_t>(nc));
  start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  auto bucket = [&](double v, int d) {
    const int n = d == 0 ? nx_ : ny_;
    return std::clamp(static_cast<int>(std::floor((v - lo_(d)) / cell_size_(d))), 0, n - 1);
  };
  for (Index c = 0; c < nc; ++c) {
    Point<2> a = mesh.vertex(mesh.cells(c, 0)), b = a;
    for (int k = 1; k < nv; ++k) {
      a = a.cwiseMin(mesh.vertex(mesh.cells(c, k)));
      b = b.cwiseMax(mesh.vertex(mesh.cells(c, k)));
    }
    range[c] = {bucket(a.x(), 0), bucket(b.x(), 0), bucket(a.y(), 1), bucket(b.y(), 1)};
    for (int j = range[c][2]; j <= range[c][3]; ++j)
      for (int i = range[c][0]; i <= range[c][1]; ++i) ++start_[static_cast<std::size_t>(j) * nx_ + i + 1];
  }
  for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
  items_.resize(static_cast<std::size_t>(start_.back()));
  std::vector<Index> fill(start_.begin(), start_.end() - 1);
  for (Index c = 0; c < nc; ++c)
    for (int j = range[c][2]; j <= range[c][3]; ++j)
      for (int i = range[c][0]; i <= range[c][1]; ++i)
        items_[fill[static_cast<std::size_t>(j) * nx_ + i]++] = c;
}

bool CellLocator::inside(Index c, const Point<2>& x, Point<2>& xi) const {
  constexpr double tol = 1e-10;
  const Point<2> v0 = mesh_.vertex(mesh_.cells(c, 0)), v1 = mesh_.vertex(mesh_.cells(c, 1));
  if (mesh_.cell_type == CellType::triangle) {
    const Point<2> v2 = mesh_.vertex(mesh_.cells(c, 2));
    Matrix<2> A;
    A << v1 - v0, v2 - v0;
    xi = A.partialPivLu().solve(x - v0);
    return xi.x() >= -tol && xi.y() >= -tol && xi.x() + xi.y() <= 1 + tol;
  }
  // Bilinear quadrilateral: Newton on x0(ξ) = x.
  const Point<2> v2 = mesh_.vertex(mesh_.cells(c, 2)), v3 = mesh_.vertex(mesh_.cells(c, 3));
  xi = Point<2>(0.5, 0.5);
  for (int it = 0; it < 20; ++it) {
    const double u = xi.x(), v = xi.y();
    const Point<2> g = (1 - u) * (1 - v) * v0 + u * (1 - v) * v1 + u * v * v2 + (1 - u) * v * v3 - x;
    Matrix<2> J;
    J.col(0) = (1 - v) * (v1 - v0) + v * (v2 - v3);
    J.col(1) = (1 - u) * (v3 - v0) + u * (v2 - v1);
    const Point<2> d = J.partialPivLu().solve(g);
    xi -= d;
    if (d.norm() < 1e-14) break;
  }
  return xi.x() >= -tol && xi.y() >= -tol && xi.x() <= 1 + tol && xi.y() <= 1 + tol;
}

CellLocator::Location CellLocator::locate(const Point<2>& x) const {
  const int i = std::clamp(static_cast<int>(std::floor((x.x() - lo_.x()) / cell_size_.x())), 0, nx_ - 1);
  const int j = std::clamp(static_cast<int>(std::floor((x.y() - lo_.y()) / cell_size_.y())), 0, ny_ - 1);
  const std::size_t b = static_cast<std::size_t>(j) * nx_ + i;
  Location loc;
  for (Index k = start_[b]; k < start_[b + 1]; ++k)
    if (inside(items_[k], x, loc.xi)) {
      loc.cell = items_[k];
      return loc;
    }
  loc.cell = -1;
  return loc;
}

}  // namespace warpfem
