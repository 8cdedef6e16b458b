#include "fem/warped_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "core/threads.hpp"
#include "fem/dof_map.hpp"
#include "fem/lagrange_element.hpp"

namespace warpfem::fem {

WarpedGeometry::WarpedGeometry(const Mesh<2>& mesh, const std::vector<Index>& cells,
                               const QuadratureRule<2>& rule, const mapping::Map<2>& map,
                               GeometryStorage storage)
    : WarpedGeometry(mesh, std::span<const Index>(), BorrowCells{}, rule, map, storage, cells) {}

WarpedGeometry::WarpedGeometry(const Mesh<2>& mesh, std::span<const Index> cells, BorrowCells,
                               const QuadratureRule<2>& rule, const mapping::Map<2>& map,
                               GeometryStorage storage)
    : WarpedGeometry(mesh, cells, BorrowCells{}, rule, map, storage, {}) {}

WarpedGeometry::WarpedGeometry(const Mesh<2>& mesh, std::span<const Index> borrowed, BorrowCells,
                               const QuadratureRule<2>& rule, const mapping::Map<2>& map,
                               GeometryStorage storage, std::vector<Index> own)
    : mesh_(&mesh),
      map_(&map),
      own_cells_(std::move(own)),
      cells_(own_cells_.empty() ? borrowed : std::span<const Index>(own_cells_)),
      rule_(rule),
      nq_(rule.size()),
      storage_(storage) {
  const LagrangeElement<2> geo(mesh.cell_type, 1);
  geo_values_ = geo.values(rule.points);
  geo_gradients_ = geo.gradients(rule.points);
  if (storage_ == GeometryStorage::streamed) return;
  const Index n = num_cells() * nq_;
  x_.resize(n, 2);
  JinvT_.resize(n, 4);
  JxW_.resize(n);

  // Whole cells per chunk; the chunks are spread over the threads (the map's own
  // threading then runs serially inside each), each with its own temporaries.
  const Index cells_per_chunk = std::max<Index>(1, build_chunk_points / std::max<Index>(1, nq_));
  const Index chunks = (num_cells() + cells_per_chunk - 1) / cells_per_chunk;
  parallel_for(chunks, 1, [&](Index first_chunk, Index last_chunk) {
    Scratch s;
    for (Index chunk = first_chunk; chunk < last_chunk; ++chunk) {
      const Index first = chunk * cells_per_chunk, last = std::min(num_cells(), first + cells_per_chunk);
      const Index offset = first * nq_;
      compute(first, last, s, x_.data() + offset, JinvT_.data() + offset, JxW_.data() + offset, n);
    }
  });
}

void WarpedGeometry::compute(Index first, Index last, Scratch& s, double* x, double* JinvT, double* JxW,
                             Index ld) const {
  const Index nc = last - first, m = nc * nq_;
  // A straight triangle is affine: J_G is one matrix per cell, so it is kept
  // per cell (rows of s.JG) and x0 = v0 + J_G ξ; other cells keep J_G per point.
  const bool affine = mesh_->cell_type == CellType::triangle;
  s.x0.resize(m, 2);
  if (affine) {
    s.JG.resize(nc, 4);
    const Points<2>& V = mesh_->vertices;
    const double *xi = rule_.points.data(), *eta = xi + nq_;
    double *X = s.x0.data(), *Y = X + m, *G = s.JG.data();
    for (Index i = 0; i < nc; ++i) {
      const TableIndex* c = &mesh_->cells(cells_[static_cast<std::size_t>(first + i)], 0);
      const double x0 = V(c[0], 0), y0 = V(c[0], 1);
      const double e = V(c[1], 0) - x0, f = V(c[2], 0) - x0, g = V(c[1], 1) - y0, h = V(c[2], 1) - y0;
      G[i] = e, G[nc + i] = f, G[2 * nc + i] = g, G[3 * nc + i] = h;
      for (Index q = 0; q < nq_; ++q) {
        X[i * nq_ + q] = x0 + e * xi[q] + f * eta[q];
        Y[i * nq_ + q] = y0 + g * xi[q] + h * eta[q];
      }
    }
  } else {
    s.JG.resize(m, 4);
    for (Index i = first; i < last; ++i)
      simple_cell_geometry(*mesh_, cells_[static_cast<std::size_t>(i)], rule_.points, geo_values_,
                           geo_gradients_, s.x0, s.JG, (i - first) * nq_);
  }
  map_->eval_with_jacobian(s.x0, s.x, s.Jf);  // one batched evaluation per chunk
  const double *Jf = s.Jf.data(), *JG = s.JG.data(), *w = rule_.weights.data();
  const double* xs = s.x.data();
  const Index ldf = s.Jf.rows(), ldg = s.JG.rows(), lds = s.x.rows();
  // J = J_f J_G, its inverse transpose and w det J; determinants are checked after
  // the loop so that it stays branch-free.
  bool inverted = false;
  for (Index i = 0; i < nc; ++i)
    for (Index q = 0; q < nq_; ++q) {
      const Index k = i * nq_ + q, kg = affine ? i : k;
      const double a = Jf[k], b = Jf[ldf + k], c = Jf[2 * ldf + k], d = Jf[3 * ldf + k];
      const double e = JG[kg], f = JG[ldg + kg], g = JG[2 * ldg + kg], h = JG[3 * ldg + kg];
      const double j00 = a * e + b * g, j01 = a * f + b * h, j10 = c * e + d * g, j11 = c * f + d * h;
      const double det = j00 * j11 - j01 * j10;
      inverted |= !(det > 0);  // also NaN
      const double inv = 1.0 / det;
      x[k] = xs[k];
      x[ld + k] = xs[lds + k];
      JinvT[k] = j11 * inv;
      JinvT[ld + k] = -j10 * inv;
      JinvT[2 * ld + k] = -j01 * inv;
      JinvT[3 * ld + k] = j00 * inv;
      JxW[k] = w[q] * det;
    }
  if (inverted) report_inverted(first, m, s);
}

void WarpedGeometry::report_inverted(Index first, Index m, const Scratch& s) const {
  // The point with the smallest det J (a NaN first), so the message always names one.
  Index worst = 0;
  double worst_det = std::numeric_limits<double>::infinity(), worst_det_f = 0;
  for (Index k = 0; k < m; ++k) {
    const double a = s.Jf(k, 0), b = s.Jf(k, 1), c = s.Jf(k, 2), d = s.Jf(k, 3);
    const Index kg = s.JG.rows() == m ? k : k / nq_;  // J_G per point or per (affine) cell
    const double e = s.JG(kg, 0), f = s.JG(kg, 1), g = s.JG(kg, 2), h = s.JG(kg, 3);
    const double det = (a * e + b * g) * (c * f + d * h) - (a * f + b * h) * (c * e + d * g);
    if (std::isnan(det) || det < worst_det) {
      worst = k, worst_det = det, worst_det_f = a * d - b * c;
      if (std::isnan(det)) break;
    }
  }
  std::ostringstream os;
  os << "the warped cell " << cells_[static_cast<std::size_t>(first + worst / nq_)]
     << " is inverted or degenerate: det J = " << worst_det << " (det J_f = " << worst_det_f << ") at x0 = ("
     << s.x0(worst, 0) << ", " << s.x0(worst, 1) << ")";
  throw Error(os.str(), {.file = "",
                         .key_path = "",
                         .hint = "the map is not bijective there; refine the map's partition (smaller "
                                 "min_interval, higher sample_resolution) or check the polygons"});
}

Index WarpedGeometry::chunk_points() {
  return thread_count() == 1 ? Index{1} << 12 : Index{1} << 16;
}

void WarpedGeometry::for_each_chunk(const std::function<void(const GeometryChunk&)>& body) const {
  if (storage_ == GeometryStorage::cached) {
    body(GeometryChunk(0, num_cells(), nq_, x_.data(), JinvT_.data(), JxW_.data(), num_cells() * nq_));
    return;
  }
  const Index cells_per_chunk = std::max<Index>(1, chunk_points() / std::max<Index>(1, nq_));
  Scratch s;
  std::vector<double> x, JinvT, JxW;
  for (Index first = 0; first < num_cells(); first += cells_per_chunk) {
    const Index last = std::min(num_cells(), first + cells_per_chunk);
    const Index m = (last - first) * nq_;
    x.resize(static_cast<std::size_t>(2 * m));
    JinvT.resize(static_cast<std::size_t>(4 * m));
    JxW.resize(static_cast<std::size_t>(m));
    compute(first, last, s, x.data(), JinvT.data(), JxW.data(), m);
    body(GeometryChunk(first, last - first, nq_, x.data(), JinvT.data(), JxW.data(), m));
  }
}

void WarpedGeometry::throw_not_cached(const char* what) {
  throw Error(
      std::string("WarpedGeometry::") + what + ": the geometry is streamed, not stored",
      {.file = "", .key_path = "", .hint = "use for_each_chunk, or build it with GeometryStorage::cached"});
}

void WarpedGeometry::cell_reference_geometry(Index i, Points<2>& x0, Jacobians<2>& JG) const {
  x0.resize(nq_, 2);
  JG.resize(nq_, 4);
  simple_cell_geometry(*mesh_, cells_[static_cast<std::size_t>(i)], rule_.points, geo_values_, geo_gradients_,
                       x0, JG, 0);
}

}  // namespace warpfem::fem
