#include "core/mesh/cell_locator.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace warpfem {

std::array<Real, 3> barycentric_coordinates(const Point<2>& a, const Point<2>& b, const Point<2>& c,
                                            const Point<2>& p) {
  const Real bx = b.x() - a.x(), by = b.y() - a.y(), cx = c.x() - a.x(), cy = c.y() - a.y();
  const Real px = p.x() - a.x(), py = p.y() - a.y();
  const Real det = bx * cy - by * cx;
  const Real l1 = (px * cy - py * cx) / det, l2 = (bx * py - by * px) / det;
  return {1 - l1 - l2, l1, l2};
}

CellLocator::CellLocator(const Mesh<2>& mesh) : CellLocator(mesh.vertices, mesh.cells, mesh.cell_type) {
  mesh.require_whole("CellLocator");
}

CellLocator::CellLocator(const Points<2>& vertices, const IndexTable& cells, CellType type)
    : vertices_(vertices), cells_(cells), type_(type) {
  require(type == CellType::triangle || type == CellType::quadrilateral,
          "CellLocator: only triangles and quadrilaterals can be located in");
  const Index nc = cells.rows();
  lo_ = vertices.colwise().minCoeff().transpose();
  const Point<2> hi = vertices.colwise().maxCoeff().transpose();
  const Point<2> extent = (hi - lo_).cwiseMax(1e-300);
  // About one cell per bucket; the slightly enlarged buckets keep the top and right edges inside the grid.
  const double per_side = std::sqrt(static_cast<double>(std::max<Index>(nc, 1)));
  const double aspect = extent.x() / extent.y();
  nx_ = std::clamp(static_cast<int>(per_side * std::sqrt(aspect)), 1, 4096);
  ny_ = std::clamp(static_cast<int>(per_side / std::sqrt(aspect)), 1, 4096);
  cell_size_ = Point<2>(extent.x() / nx_, extent.y() / ny_) * (1 + 1e-12);
  const int nv = vertices_per_cell(type);
  std::vector<std::array<int, 4>> range(static_cast<std::size_t>(nc));
  start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  auto bucket = [&](double v, int d) {
    const int n = d == 0 ? nx_ : ny_;
    return std::clamp(static_cast<int>(std::floor((v - lo_(d)) / cell_size_(d))), 0, n - 1);
  };
  for (Index c = 0; c < nc; ++c) {
    Point<2> a = vertices.row(cells(c, 0)).transpose(), b = a;
    for (int k = 1; k < nv; ++k) {
      a = a.cwiseMin(vertices.row(cells(c, k)).transpose());
      b = b.cwiseMax(vertices.row(cells(c, k)).transpose());
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
  auto corner = [&](int k) -> Point<2> { return vertices_.row(cells_(c, k)).transpose(); };
  const Point<2> v0 = corner(0), v1 = corner(1);
  if (type_ == CellType::triangle) {
    const Point<2> v2 = corner(2);
    Matrix<2> A;
    A << v1 - v0, v2 - v0;
    xi = A.partialPivLu().solve(x - v0);
    return xi.x() >= -tol && xi.y() >= -tol && xi.x() + xi.y() <= 1 + tol;
  }
  // Bilinear quadrilateral: Newton on x0(ξ) = x.
  const Point<2> v2 = corner(2), v3 = corner(3);
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

CellLocator::Nearest CellLocator::nearest(const Point<2>& x) const {
  require(type_ == CellType::triangle, "CellLocator::nearest: needs a triangle mesh");
  Nearest best;
  Real best_min = -std::numeric_limits<Real>::infinity();
  const int ci = std::clamp(static_cast<int>(std::floor((x.x() - lo_.x()) / cell_size_.x())), 0, nx_ - 1);
  const int cj = std::clamp(static_cast<int>(std::floor((x.y() - lo_.y()) / cell_size_.y())), 0, ny_ - 1);
  // Every triangle whose bounding box holds x is in x's own bucket (ring 0);
  // the rings around it are searched only when x is in none of them.
  const int max_ring = std::max(nx_, ny_);
  for (int ring = 0; ring <= max_ring; ++ring) {
    for (int j = std::max(cj - ring, 0); j <= std::min(cj + ring, ny_ - 1); ++j) {
      const bool whole_row = std::abs(j - cj) == ring;
      for (int i = std::max(ci - ring, 0); i <= std::min(ci + ring, nx_ - 1); ++i) {
        if (!whole_row && std::abs(i - ci) != ring) continue;  // only the ring's buckets
        const std::size_t b = static_cast<std::size_t>(j) * nx_ + i;
        for (Index k = start_[b]; k < start_[b + 1]; ++k) {
          const Index c = items_[static_cast<std::size_t>(k)];
          const auto l = barycentric_coordinates(vertices_.row(cells_(c, 0)).transpose(),
                                                 vertices_.row(cells_(c, 1)).transpose(),
                                                 vertices_.row(cells_(c, 2)).transpose(), x);
          const Real m = std::min({l[0], l[1], l[2]});
          if (m > best_min) {
            best_min = m;
            best.cell = c;
            best.barycentric = l;
          }
        }
      }
    }
    if (best_min >= -1e-12) break;           // found a containing triangle
    if (best.cell >= 0 && ring >= 1) break;  // outside: the nearby best is good enough
  }
  best.inside = best_min >= -1e-12;
  if (!best.inside && best.cell >= 0) {
    Real s = 0;
    for (Real& l : best.barycentric) s += (l = std::max(l, Real{0}));
    for (Real& l : best.barycentric) l /= s;
  }
  return best;
}

}  // namespace warpfem
