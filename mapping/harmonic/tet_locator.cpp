#include "mapping/harmonic/tet_locator.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace warpfem::mapping {

bool is_flat(const Matrix<3>& edges, Real relative_volume) {
  const Real longest = std::max({edges.col(0).norm(), edges.col(1).norm(), edges.col(2).norm(),
                                 (edges.col(1) - edges.col(0)).norm(), (edges.col(2) - edges.col(0)).norm(),
                                 (edges.col(2) - edges.col(1)).norm()});
  return !(std::abs(edges.determinant()) > relative_volume * longest * longest * longest);
}

TetLocator::TetLocator(const Points<3>& vertices, const IndexTable& cells)
    : vertices_(vertices), cells_(cells) {
  require(cells.cols() == 4, "TetLocator: the cells must be tetrahedra");
  const Index nc = cells.rows();
  require(nc > 0 && vertices.rows() > 0, "TetLocator: no cells to locate in");
  lo_ = vertices.colwise().minCoeff().transpose();
  const Point<3> hi = vertices.colwise().maxCoeff().transpose();
  const Point<3> extent = (hi - lo_).cwiseMax(1e-300 + 1e-12 * (hi - lo_).maxCoeff());
  // About one cell per bucket, buckets as cubic as the extent allows.
  const Real side = std::cbrt(extent.prod() / static_cast<Real>(nc));
  for (int d = 0; d < 3; ++d) n_[d] = std::clamp(static_cast<int>(extent(d) / side), 1, 512);
  // Slightly enlarged buckets keep the upper faces inside the grid.
  for (int d = 0; d < 3; ++d) bucket_size_(d) = extent(d) / n_[d] * (1 + 1e-12);
  inverse_edges_.resize(static_cast<std::size_t>(nc));
  std::vector<std::array<int, 6>> range(static_cast<std::size_t>(nc));
  start_.assign(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2] + 1, 0);
  const auto for_buckets = [&](const std::array<int, 6>& r, auto&& f) {
    for (int k = r[4]; k <= r[5]; ++k)
      for (int j = r[2]; j <= r[3]; ++j)
        for (int i = r[0]; i <= r[1]; ++i) f((static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i);
  };
  for (Index c = 0; c < nc; ++c) {
    const Point<3> v0 = vertices.row(cells(c, 0)).transpose();
    Point<3> a = v0, b = v0;
    Matrix<3> E;
    for (int k = 1; k < 4; ++k) {
      const Point<3> v = vertices.row(cells(c, k)).transpose();
      a = a.cwiseMin(v), b = b.cwiseMax(v);
      E.col(k - 1) = v - v0;
    }
    inverse_edges_[static_cast<std::size_t>(c)] = E.inverse();
    auto& r = range[static_cast<std::size_t>(c)];
    if (is_flat(E)) {
      r = {0, -1, 0, -1, 0, -1};  // in no bucket
      continue;
    }
    for (int d = 0; d < 3; ++d) r[2 * d] = bucket(a(d), d), r[2 * d + 1] = bucket(b(d), d);
    for_buckets(r, [&](std::size_t q) { ++start_[q + 1]; });
  }
  for (std::size_t q = 1; q < start_.size(); ++q) start_[q] += start_[q - 1];
  items_.resize(static_cast<std::size_t>(start_.back()));
  std::vector<Index> fill(start_.begin(), start_.end() - 1);
  for (Index c = 0; c < nc; ++c)
    for_buckets(range[static_cast<std::size_t>(c)],
                [&](std::size_t q) { items_[static_cast<std::size_t>(fill[q]++)] = c; });
}

int TetLocator::bucket(Real v, int d) const {
  const Real q = std::floor((v - lo_(d)) / bucket_size_(d));
  return std::isfinite(q) ? static_cast<int>(std::clamp<Real>(q, 0, n_[d] - 1)) : 0;
}

TetLocator::Location TetLocator::locate(const Point<3>& x) const {
  Location best;
  Real best_least = -std::numeric_limits<Real>::infinity();
  const std::size_t q =
      (static_cast<std::size_t>(bucket(x.z(), 2)) * n_[1] + bucket(x.y(), 1)) * n_[0] + bucket(x.x(), 0);
  for (Index s = start_[q]; s < start_[q + 1]; ++s) {
    const Index c = items_[static_cast<std::size_t>(s)];
    const Point<3> l =
        inverse_edges_[static_cast<std::size_t>(c)] * (x - vertices_.row(cells_(c, 0)).transpose());
    const Location here{c, {1 - l.sum(), l(0), l(1), l(2)}};
    const Real least = here.least();
    if (least > best_least) {
      best = here, best_least = least;
      if (least >= 0) break;
    }
  }
  return best;
}

}  // namespace warpfem::mapping
