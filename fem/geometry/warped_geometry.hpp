#pragma once
// Geometry of the warped cells f(T) at the quadrature points of a set of cells
// (thesis eq. 9.2–9.4):
//   x0 = G(ξ) (point in Ω0), x = f(x0), J = J_f(x0) · J_G(ξ), J^{-T}, w |det J|.
//
// Two storage modes:
//  - cached (default): computed once from batched calls of the map and kept.
//    Assembly, Newton iterations and time steps read these arrays and never
//    evaluate f again.
//  - streamed: nothing is kept; every pass (for_each_chunk) evaluates the map
//    again, chunk by chunk. For operators assembled once (multigrid coarse
//    levels, a linear problem solved once) this saves the memory — the
//    largest array of a Poisson problem — and the time to fill it.
//
// Only what assembly reads is kept: x (dim numbers), J^{-T} (dim²) and w det J
// per quadrature point; x0 and J_G are recomputed from the simple mesh when a
// caller needs them (cell_reference_geometry), and J_f = J · J_G⁻¹. The map is
// evaluated chunk by chunk so that its temporaries stay small.
//
// This class and WarpedFacets (boundary facets) are the only places in fem/
// that evaluate the map at quadrature points; CellValues reads them.

#include <array>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "core/mesh/mesh.hpp"
#include "core/mesh/quadrature.hpp"
#include "fem/reference/lagrange_element.hpp"
#include "mapping/map.hpp"

namespace warpfem::fem {

enum class GeometryStorage { cached, streamed };

/// The geometry of the cells [first_cell, first_cell + num_cells) of a
/// WarpedGeometry's cells(), quadrature point q of local cell i at at(i, q).
template <int dim>
class GeometryChunk {
 public:
  GeometryChunk(Index first_cell, Index num_cells, Index nq, const double* x, const double* JinvT,
                const double* JxW, Index ld)
      : first_(first_cell), cells_(num_cells), nq_(nq), x_(x), J_(JinvT), w_(JxW), ld_(ld) {}

  Index first_cell() const { return first_; }
  Index num_cells() const { return cells_; }
  Index points_per_cell() const { return nq_; }
  Index at(Index i, Index q) const { return i * nq_ + q; }
  /// Component d of x = f(x0).
  double x(Index p, int d) const { return x_[d * ld_ + p]; }
  Point<dim> point(Index p) const {
    Point<dim> x;
    for (int d = 0; d < dim; ++d) x[d] = x_[d * ld_ + p];
    return x;
  }
  /// Entry k of J^{-T} (row-major: k = dim · row + column).
  double inverse_transpose(Index p, int k) const { return J_[k * ld_ + p]; }
  Matrix<dim> inverse_transpose_matrix(Index p) const {
    Matrix<dim> m;
    for (int r = 0; r < dim; ++r)
      for (int c = 0; c < dim; ++c) m(r, c) = J_[(r * dim + c) * ld_ + p];
    return m;
  }
  /// w_q |det J|.
  double JxW(Index p) const { return w_[p]; }
  /// The raw arrays (component / entry k at offset k · leading_dimension()).
  const double* x_data() const { return x_; }
  const double* inverse_transpose_data() const { return J_; }
  const double* JxW_data() const { return w_; }
  Index leading_dimension() const { return ld_; }

 private:
  Index first_, cells_, nq_;
  const double *x_, *J_, *w_;
  Index ld_;
};

template <int dim>
class WarpedGeometry {
 public:
  /// Throws warpfem::Error naming the cell and position if det J <= 0 anywhere
  /// (streamed: when a pass reaches that cell).
  WarpedGeometry(const Mesh<dim>& mesh, const std::vector<Index>& cells, const QuadratureRule<dim>& rule,
                 const mapping::Map<dim>& map, GeometryStorage storage = GeometryStorage::cached);
  /// The same over cells the caller keeps (no copy; `cells`' storage must stay
  /// where it is while the geometry lives, e.g. DofDistribution::local_cells()
  /// of the same problem).
  struct BorrowCells {};
  WarpedGeometry(const Mesh<dim>& mesh, std::span<const Index> cells, BorrowCells,
                 const QuadratureRule<dim>& rule, const mapping::Map<dim>& map,
                 GeometryStorage storage = GeometryStorage::cached);
  WarpedGeometry(WarpedGeometry&&) = default;
  WarpedGeometry& operator=(WarpedGeometry&&) = default;
  WarpedGeometry(const WarpedGeometry&) = delete;  // cells_ may view own_cells_
  WarpedGeometry& operator=(const WarpedGeometry&) = delete;

  Index num_cells() const { return static_cast<Index>(cells_.size()); }
  Index points_per_cell() const { return nq_; }
  /// Flat index of quadrature point q of the i-th cell of cells().
  Index at(Index i, Index q) const { return i * nq_ + q; }
  std::span<const Index> cells() const { return cells_; }
  const Mesh<dim>& mesh() const { return *mesh_; }
  const QuadratureRule<dim>& rule() const { return rule_; }
  GeometryStorage storage() const { return storage_; }
  /// Frees the cached arrays: later passes evaluate the map again, as streamed
  /// storage does.
  void stop_caching() {
    storage_ = GeometryStorage::streamed;
    x_ = {};
    JinvT_ = {};
    JxW_ = {};
  }

  /// Calls body(chunk) for consecutive chunks covering all cells, in order
  /// (cached: one chunk viewing the stored arrays; streamed: the map evaluated
  /// per chunk of chunk_points points). The map must outlive a streamed geometry.
  /// A template forced inline, so that the body (an assembly loop) inlines into its caller.
  template <class Body>
  [[gnu::always_inline]] void for_each_chunk(Body&& body) const {
    if (storage_ == GeometryStorage::cached) {
      body(GeometryChunk<dim>(0, num_cells(), nq_, x_.data(), JinvT_.data(), JxW_.data(), num_cells() * nq_));
      return;
    }
    StreamBuffers b;
    for (Index first = 0; first < num_cells(); first = b.last) {
      compute_streamed_chunk(first, b);
      body(GeometryChunk<dim>(first, b.last - first, nq_, b.x.data(), b.JinvT.data(), b.JxW.data(),
                              (b.last - first) * nq_));
    }
  }

  /// The whole arrays (cached storage only; throws otherwise).
  const Points<dim>& physical_points() const {  ///< f(x0) in Ω1
    if (storage_ != GeometryStorage::cached) throw_not_cached("physical_points");
    return x_;
  }
  const Jacobians<dim>& inverse_transpose() const {
    if (storage_ != GeometryStorage::cached) throw_not_cached("inverse_transpose");
    return JinvT_;
  }
  const VectorX& JxW() const {  ///< w_q |det J|
    if (storage_ != GeometryStorage::cached) throw_not_cached("JxW");
    return JxW_;
  }

  /// x0 = G(ξ_q) and J_G(ξ_q) of the simple (unwarped) cell cells()[i], one row per
  /// quadrature point: recomputed from the mesh, not stored.
  void cell_reference_geometry(Index i, Points<dim>& x0, Jacobians<dim>& JG) const;

  /// Points per chunk of a streamed pass (one batched map evaluation per
  /// chunk, spread over the threads by the map): on one thread small enough
  /// for the chunk's temporaries to stay in L2, with more threads large enough
  /// for the map's threads to share it (measured: BENCHMARKS.md).
  static Index chunk_points();
  /// Points per chunk when the cached arrays are filled: the chunks go to the
  /// threads whole, and a chunk's temporaries (~100 bytes per point) stay in L2.
  static constexpr Index build_chunk_points = Index{1} << 12;

 private:
  /// Scratch of one chunk computation.
  struct Scratch;
  /// Arrays of one streamed chunk.
  struct StreamBuffers {
    std::vector<double> x, JinvT, JxW;
    std::shared_ptr<Scratch> scratch;
    Index last = 0;
  };
  /// Fills `b` for the cells [first, b.last) of one streamed chunk.
  void compute_streamed_chunk(Index first, StreamBuffers& b) const;
  struct Scratch {
    Points<dim> x0, x;
    Jacobians<dim> JG, Jf;  ///< J_G one row per point, or per cell for (affine) simplices
  };
  /// Cells [first, last): x, J^{-T}, JxW written with leading dimension ld at
  /// offset 0 of the given arrays.
  void compute(Index first, Index last, Scratch& s, double* x, double* JinvT, double* JxW, Index ld) const;
  /// The constructors' common part: the cells are `own` if given, else `borrowed`.
  WarpedGeometry(const Mesh<dim>& mesh, std::span<const Index> borrowed, BorrowCells,
                 const QuadratureRule<dim>& rule, const mapping::Map<dim>& map, GeometryStorage storage,
                 std::vector<Index> own);
  /// Throws naming the chunk's point with the smallest det J (or a NaN).
  [[noreturn]] void report_inverted(Index first, Index m, const Scratch& s) const;
  [[noreturn]] static void throw_not_cached(const char* what);

  const Mesh<dim>* mesh_;
  const mapping::Map<dim>* map_;
  std::vector<Index> own_cells_;  // empty when the cells are borrowed
  std::span<const Index> cells_;  // own_cells_, or the caller's (a vector's buffer survives moves)
  QuadratureRule<dim> rule_;
  Index nq_ = 0;
  GeometryStorage storage_;
  MatrixX geo_values_;
  std::array<MatrixX, dim> geo_gradients_;
  Points<dim> x_;
  Jacobians<dim> JinvT_;
  VectorX JxW_;
};

/// f at the nodes x0 (one batched evaluation): the positions of DOF nodes on
/// Ω1 for boundary data, initial states, rigid-body modes and output, and
/// det J_f there if `det_jacobian` is given. Throws naming the first node
/// where f is not finite.
template <int dim>
Points<dim> warp_nodes(const mapping::Map<dim>& map, const Points<dim>& x0, VectorX* det_jacobian = nullptr);

}  // namespace warpfem::fem
