#include "fem/geometry/warped_geometry.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/cofactor.hpp"
#include "core/error.hpp"
#include "core/prefault.hpp"
#include "core/threads.hpp"
#include "fem/geometry/simple_cell_geometry.hpp"

namespace warpfem::fem {

template <int dim>
WarpedGeometry<dim>::WarpedGeometry(const Mesh<dim>& mesh, const std::vector<Index>& cells,
                                    const QuadratureRule<dim>& rule, const mapping::Map<dim>& map,
                                    GeometryStorage storage)
    : WarpedGeometry(mesh, std::span<const Index>(), BorrowCells{}, rule, map, storage, cells) {}

template <int dim>
WarpedGeometry<dim>::WarpedGeometry(const Mesh<dim>& mesh, std::span<const Index> cells, BorrowCells,
                                    const QuadratureRule<dim>& rule, const mapping::Map<dim>& map,
                                    GeometryStorage storage)
    : WarpedGeometry(mesh, cells, BorrowCells{}, rule, map, storage, {}) {}

template <int dim>
WarpedGeometry<dim>::WarpedGeometry(const Mesh<dim>& mesh, std::span<const Index> borrowed, BorrowCells,
                                    const QuadratureRule<dim>& rule, const mapping::Map<dim>& map,
                                    GeometryStorage storage, std::vector<Index> own)
    : mesh_(&mesh),
      map_(&map),
      own_cells_(std::move(own)),
      cells_(own_cells_.empty() ? borrowed : std::span<const Index>(own_cells_)),
      rule_(rule),
      nq_(rule.size()),
      storage_(storage) {
  const LagrangeElement<dim> geo(mesh.cell_type, 1);
  geo_values_ = geo.values(rule.points);
  geo_gradients_ = geo.gradients(rule.points);
  if (storage_ == GeometryStorage::streamed) return;
  const Index n = num_cells() * nq_;
  x_.resize(n, dim);
  JinvT_.resize(n, dim * dim);
  JxW_.resize(n);
  // The largest fresh arrays of a problem: backed in one call each, not page by page.
  prefault(x_.data(), static_cast<std::size_t>(x_.size()) * sizeof(double));
  prefault(JinvT_.data(), static_cast<std::size_t>(JinvT_.size()) * sizeof(double));
  prefault(JxW_.data(), static_cast<std::size_t>(JxW_.size()) * sizeof(double));

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

template <int dim>
void WarpedGeometry<dim>::compute(Index first, Index last, Scratch& s, double* x, double* JinvT, double* JxW,
                                  Index ld) const {
  const Index nc = last - first, m = nc * nq_;
  // A straight simplex is affine: J_G is one matrix per cell, so it is kept
  // per cell (rows of s.JG) and x0 = v0 + J_G ξ; other cells keep J_G per point.
  const bool affine = vertices_per_cell(mesh_->cell_type) == dim + 1;
  s.x0.resize(m, dim);
  if (affine) {
    s.JG.resize(nc, dim * dim);
    const Points<dim>& V = mesh_->vertices;
    const double* xi = rule_.points.data();
    double *X = s.x0.data(), *G = s.JG.data();
    for (Index i = 0; i < nc; ++i) {
      const TableIndex* c = &mesh_->cells(cells_[static_cast<std::size_t>(first + i)], 0);
      double v0[dim], e[dim][dim];  // e[r][j]: component r of edge v_{j+1} − v0
      for (int r = 0; r < dim; ++r) {
        v0[r] = V(c[0], r);
        for (int j = 0; j < dim; ++j) e[r][j] = V(c[j + 1], r) - v0[r];
      }
      for (int r = 0; r < dim; ++r)
        for (int j = 0; j < dim; ++j) G[(r * dim + j) * nc + i] = e[r][j];
      for (Index q = 0; q < nq_; ++q)
        for (int r = 0; r < dim; ++r) {
          double xr = v0[r];
          for (int j = 0; j < dim; ++j) xr += e[r][j] * xi[j * nq_ + q];
          X[r * m + i * nq_ + q] = xr;
        }
    }
  } else {
    s.JG.resize(m, dim * dim);
    for (Index i = first; i < last; ++i)
      simple_cell_geometry<dim>(*mesh_, cells_[static_cast<std::size_t>(i)], nq_, geo_values_, geo_gradients_,
                                s.x0, s.JG, (i - first) * nq_);
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
      Matrix<dim> A, B;
      for (int r = 0; r < dim; ++r)
        for (int c = 0; c < dim; ++c) {
          A(r, c) = Jf[(r * dim + c) * ldf + k];
          B(r, c) = JG[(r * dim + c) * ldg + kg];
        }
      const Matrix<dim> J = A * B;
      const Matrix<dim> cof = cofactor<dim>(J);
      const double det = determinant_from_cofactor<dim>(J, cof);
      inverted |= !(det > 0);  // also NaN
      const double inv = 1.0 / det;
      for (int d = 0; d < dim; ++d) x[d * ld + k] = xs[d * lds + k];
      for (int r = 0; r < dim; ++r)
        for (int c = 0; c < dim; ++c) JinvT[(r * dim + c) * ld + k] = cof(r, c) * inv;
      JxW[k] = w[q] * det;
    }
  if (inverted) report_inverted(first, m, s);
}

template <int dim>
void WarpedGeometry<dim>::report_inverted(Index first, Index m, const Scratch& s) const {
  // The point with the smallest det J (a NaN first), so the message always names one.
  Index worst = 0;
  double worst_det = std::numeric_limits<double>::infinity(), worst_det_f = 0;
  for (Index k = 0; k < m; ++k) {
    const Index kg = s.JG.rows() == m ? k : k / nq_;  // J_G per point or per (affine) cell
    const Matrix<dim> Jf = jacobian_at<dim>(s.Jf, k);
    const double det = (Jf * jacobian_at<dim>(s.JG, kg)).determinant();
    if (std::isnan(det) || det < worst_det) {
      worst = k, worst_det = det, worst_det_f = Jf.determinant();
      if (std::isnan(det)) break;
    }
  }
  std::ostringstream os;
  os << "the warped cell " << cells_[static_cast<std::size_t>(first + worst / nq_)]
     << " is inverted or degenerate: det J = " << worst_det << " (det J_f = " << worst_det_f << ") at x0 = (";
  for (int d = 0; d < dim; ++d) os << (d ? ", " : "") << s.x0(worst, d);
  os << ")";
  throw Error(os.str(), {.file = "",
                         .key_path = "",
                         .hint = "the map is not bijective there; refine the map's partition (smaller "
                                 "min_interval, higher sample_resolution) or check the polygons"});
}

template <int dim>
Index WarpedGeometry<dim>::chunk_points() {
  return thread_count() == 1 ? Index{1} << 12 : Index{1} << 16;
}

template <int dim>
void WarpedGeometry<dim>::compute_streamed_chunk(Index first, StreamBuffers& b) const {
  const Index cells_per_chunk = std::max<Index>(1, chunk_points() / std::max<Index>(1, nq_));
  if (!b.scratch) b.scratch = std::make_shared<Scratch>();
  b.last = std::min(num_cells(), first + cells_per_chunk);
  const Index m = (b.last - first) * nq_;
  b.x.resize(static_cast<std::size_t>(dim * m));
  b.JinvT.resize(static_cast<std::size_t>(dim * dim * m));
  b.JxW.resize(static_cast<std::size_t>(m));
  compute(first, b.last, *b.scratch, b.x.data(), b.JinvT.data(), b.JxW.data(), m);
}

template <int dim>
void WarpedGeometry<dim>::throw_not_cached(const char* what) {
  throw Error(
      std::string("WarpedGeometry::") + what + ": the geometry is streamed, not stored",
      {.file = "", .key_path = "", .hint = "use for_each_chunk, or build it with GeometryStorage::cached"});
}

template <int dim>
void WarpedGeometry<dim>::cell_reference_geometry(Index i, Points<dim>& x0, Jacobians<dim>& JG) const {
  x0.resize(nq_, dim);
  JG.resize(nq_, dim * dim);
  simple_cell_geometry<dim>(*mesh_, cells_[static_cast<std::size_t>(i)], nq_, geo_values_, geo_gradients_, x0,
                            JG, 0);
}

template <int dim>
Points<dim> warp_nodes(const mapping::Map<dim>& map, const Points<dim>& x0, VectorX* det_jacobian) {
  Points<dim> x;
  if (det_jacobian) {
    Jacobians<dim> J;
    map.eval_with_jacobian(x0, x, J);
    det_jacobian->resize(x0.rows());
    for (Index p = 0; p < x0.rows(); ++p) (*det_jacobian)(p) = jacobian_at<dim>(J, p).determinant();
  } else {
    map.eval(x0, x);
  }
  for (Index p = 0; p < x.rows(); ++p)
    if (!x.row(p).allFinite()) {
      std::ostringstream os;
      os << "the map is not finite at the node x0 = (";
      for (int d = 0; d < dim; ++d) os << (d ? ", " : "") << x0(p, d);
      os << ")";
      throw Error(os.str(), {.file = "", .key_path = "", .hint = "check the map's polygons"});
    }
  return x;
}

template class WarpedGeometry<2>;
template class WarpedGeometry<3>;
template Points<2> warp_nodes<2>(const mapping::Map<2>&, const Points<2>&, VectorX*);
template Points<3> warp_nodes<3>(const mapping::Map<3>&, const Points<3>&, VectorX*);

}  // namespace warpfem::fem
