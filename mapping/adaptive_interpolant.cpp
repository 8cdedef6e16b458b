#include "mapping/adaptive_interpolant.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <utility>

#include "core/collective_error.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"
#include "mapping/detail/mean_value_kernel.hpp"

namespace warpfem::mapping {
namespace {

constexpr int kComponents = 6;  // f_x, f_y, J00, J01, J10, J11
constexpr int kMaxDegree = 31;

Real orient(const Point<2>& a, const Point<2>& b, Real x, Real y) {
  return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
}

// Conservative: true if segment ab may meet the closed box.
bool segment_meets_box(const Point<2>& a, const Point<2>& b, Real x0, Real y0, Real x1, Real y1) {
  if (std::max(a.x(), b.x()) < x0 || std::min(a.x(), b.x()) > x1) return false;
  if (std::max(a.y(), b.y()) < y0 || std::min(a.y(), b.y()) > y1) return false;
  const Real s[4] = {orient(a, b, x0, y0), orient(a, b, x1, y0), orient(a, b, x0, y1), orient(a, b, x1, y1)};
  const bool all_pos = s[0] > 0 && s[1] > 0 && s[2] > 0 && s[3] > 0;
  const bool all_neg = s[0] < 0 && s[1] < 0 && s[2] < 0 && s[3] < 0;
  return !all_pos && !all_neg;
}

// Is p in the closed Ω0, given that the centre c of a cell has status
// `c_inside` and `edges` holds every edge of ∂Ω0 meeting the cell? The segment
// c → p stays in the cell, so only those edges can cross it, and none of their
// end points lies in the cell (cells near vertices are never interpolated).
bool inside_by_parity(const Polygon& s, const int* edges, int count, Real cx, Real cy, bool c_inside, Real x,
                      Real y) {
  const Point<2> c(cx, cy), p(x, y);
  bool in = c_inside;
  for (int k = 0; k < count; ++k) {
    const Point<2>& a = s.vertex(edges[k]);
    const Point<2>& b = s.vertex(edges[k] + 1);
    const Real op = orient(a, b, x, y);
    if (op == 0 && (a - p).dot(b - p) <= 0) return true;  // on ∂Ω0
    const Real oc = orient(a, b, cx, cy);
    if ((oc > 0) == (op > 0)) continue;
    const Real oa = orient(c, p, a.x(), a.y()), ob = orient(c, p, b.x(), b.y());
    if ((oa > 0) != (ob > 0)) in = !in;
  }
  return in;
}

inline void chebyshev(Real u, int n, Real* t) {
  t[0] = 1;
  if (n > 0) t[1] = u;
  for (int k = 2; k <= n; ++k) t[k] = 2 * u * t[k - 1] - t[k - 2];
}

// out[c - first] = Σ_ij C_c(i, j) T_i(u) T_j(v) for components [first, last);
// C_c(i, j) is at C[c·n1·P + i + j·P] with i padded by zero coefficients to the
// compile-time stride P (a multiple of 4), four of them per vector operation.
// Four doubles: GCC/Clang lower it to one AVX register in the AVX clones and to
// two SSE registers otherwise (auto-vectorization leaves these short loops scalar).
typedef Real Real4 __attribute__((vector_size(32)));

template <int P>
WARPFEM_KERNEL_INLINE void evaluate_leaf_padded(const Real* C, int n1, Real u, Real v, int first, int last,
                                                Real* out) {
  constexpr int V = P / 4;
  alignas(32) Real tx[P], ty[P];
  chebyshev(u, P - 1, tx);
  chebyshev(v, n1 - 1, ty);
  Real4 txv[V];
  std::memcpy(txv, tx, sizeof tx);
  for (int c = first; c < last; ++c) {
    const Real* Cc = C + c * n1 * P;
    Real4 r[V] = {};
    for (int j = 0; j < n1; ++j)
      for (int k = 0; k < V; ++k) {
        Real4 cv;
        std::memcpy(&cv, Cc + j * P + 4 * k, sizeof cv);
        r[k] += cv * ty[j];
      }
    Real4 acc = r[0] * txv[0];
    for (int k = 1; k < V; ++k) acc += r[k] * txv[k];
    out[c - first] = (acc[0] + acc[1]) + (acc[2] + acc[3]);
  }
}

WARPFEM_KERNEL_CLONES void evaluate_leaf(const Real* C, int n1, Real u, Real v, int first, int last,
                                         Real* out) {
  switch ((n1 + 3) / 4) {
    case 1: return evaluate_leaf_padded<4>(C, n1, u, v, first, last, out);
    case 2: return evaluate_leaf_padded<8>(C, n1, u, v, first, last, out);
    case 3: return evaluate_leaf_padded<12>(C, n1, u, v, first, last, out);
    case 4: return evaluate_leaf_padded<16>(C, n1, u, v, first, last, out);
    case 5: return evaluate_leaf_padded<20>(C, n1, u, v, first, last, out);
    case 6: return evaluate_leaf_padded<24>(C, n1, u, v, first, last, out);
    case 7: return evaluate_leaf_padded<28>(C, n1, u, v, first, last, out);
    default: return evaluate_leaf_padded<32>(C, n1, u, v, first, last, out);
  }
}

// The same sums for eight points of one leaf at a time, one point per vector
// lane: out[(c − first) · 8 + lane]. Every lane runs the same operations, so a
// point's values do not depend on the other points of its batch (unused lanes
// repeat a point). Eleven independent accumulators (one per j) keep the FMA
// pipes busy; with AVX-512 a lane vector is one register.
typedef Real Real8 __attribute__((vector_size(64)));
constexpr int kLanes = 8;
constexpr int kMaxBatchedN1 = 16;

// GCC 12 reports the fully assigned lane arrays below as maybe uninitialized
// once they are inlined into the AVX-512 clone (a false positive).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
template <int N1>
WARPFEM_KERNEL_INLINE void evaluate_leaf8_fixed(const Real* C, const Real* u, const Real* v, int first,
                                                int last, Real* out) {
  constexpr int P = (N1 + 3) / 4 * 4;
  Real8 U, V;
  std::memcpy(&U, u, sizeof U);
  std::memcpy(&V, v, sizeof V);
  const Real8 U2 = U + U, V2 = V + V;
  Real8 tx[N1], ty[N1];
  tx[0] = ty[0] = Real8{1, 1, 1, 1, 1, 1, 1, 1};
  if constexpr (N1 > 1) tx[1] = U, ty[1] = V;
  for (int k = 2; k < N1; ++k) {
    tx[k] = U2 * tx[k - 1] - tx[k - 2];
    ty[k] = V2 * ty[k - 1] - ty[k - 2];
  }
  for (int c = first; c < last; ++c) {
    const Real* Cc = C + c * N1 * P;
    Real8 r[N1];
    for (int j = 0; j < N1; ++j) {  // T_0 = 1
      const Real a = Cc[j * P];
      r[j] = Real8{a, a, a, a, a, a, a, a};
    }
    for (int i = 1; i < N1; ++i)
      for (int j = 0; j < N1; ++j) {
        const Real a = Cc[j * P + i];
        r[j] += Real8{a, a, a, a, a, a, a, a} * tx[i];
      }
    Real8 acc = r[0] * ty[0];
    for (int j = 1; j < N1; ++j) acc += r[j] * ty[j];
    std::memcpy(out + (c - first) * kLanes, &acc, sizeof acc);
  }
}

template <int... N>
WARPFEM_KERNEL_INLINE void evaluate_leaf8_dispatch(std::integer_sequence<int, N...>, const Real* C, int n1,
                                                   const Real* u, const Real* v, int first, int last,
                                                   Real* out) {
  (void)((n1 == N + 1 ? (evaluate_leaf8_fixed<N + 1>(C, u, v, first, last, out), true) : false) || ...);
}

// n1 in [1, kMaxBatchedN1].
WARPFEM_KERNEL_CLONES void evaluate_leaf8(const Real* C, int n1, const Real* u, const Real* v, int first,
                                          int last, Real* out) {
  evaluate_leaf8_dispatch(std::make_integer_sequence<int, kMaxBatchedN1>{}, C, n1, u, v, first, last, out);
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// One point through the batched kernel (its lane repeated), for the same values as in a batch.
void evaluate_leaf_one(const Real* C, int n1, Real u, Real v, int first, int last, Real* out) {
  if (n1 > kMaxBatchedN1) return evaluate_leaf(C, n1, u, v, first, last, out);
  alignas(64) Real bu[kLanes], bv[kLanes], res[kComponents * kLanes];
  std::fill(bu, bu + kLanes, u);
  std::fill(bv, bv + kLanes, v);
  evaluate_leaf8(C, n1, bu, bv, first, last, res);
  for (int c = first; c < last; ++c) out[c - first] = res[(c - first) * kLanes];
}

int padded(int n1) {
  return (n1 + 3) / 4 * 4;
}

Real halton(int index, int base) {
  Real f = 1, r = 0;
  for (int i = index; i > 0; i /= base) {
    f /= base;
    r += f * (i % base);
  }
  return r;
}

}  // namespace

class AdaptiveInterpolant::Builder {
 public:
  explicit Builder(AdaptiveInterpolant& m) : m_(m), o_(m.options_), n1_(o_.degree + 1) {
    const Polygon& s = m_.source_;
    const Point<2> lo = s.bbox_min(), hi = s.bbox_max();
    diam_ = (hi - lo).norm();
    side_ = std::max(hi.x() - lo.x(), hi.y() - lo.y()) * (1 + 1e-9);
    const Point<2> mid = (lo + hi) / 2;
    tol_f_ = o_.tolerance * diam_;
    tol_J_ = 1000 * o_.tolerance;
    M_.resize(n1_, n1_);
    nodes_u_.resize(n1_);
    for (int k = 0; k < n1_; ++k) nodes_u_[k] = std::cos(std::numbers::pi * (k + 0.5) / n1_);
    for (int i = 0; i < n1_; ++i)
      for (int k = 0; k < n1_; ++k)
        M_(i, k) = (i == 0 ? 1.0 : 2.0) / n1_ * std::cos(i * std::numbers::pi * (k + 0.5) / n1_);
    // Test points spread over the cell, denser towards its sides (where the
    // interpolation error of a Chebyshev fit peaks).
    for (int t = 1; t <= o_.test_points; ++t)
      tests_.emplace_back(std::sin(std::numbers::pi / 2 * (2 * halton(t, 2) - 1)),
                          std::sin(std::numbers::pi / 2 * (2 * halton(t, 3) - 1)));
    m_.nodes_.push_back(Node{mid.x() - side_ / 2, mid.y() - side_ / 2, side_});
  }

  // The tree is built level by level: every rank classifies the cells of a
  // level (cheap, the same everywhere), fits a deterministic share of those
  // that need a fit (candidate k on rank k mod size, on the rank's threads),
  // and the fits are all-gathered, so every rank ends with the same tree and
  // the same coefficients as a build on one rank.
  void build(MPI_Comm comm) {
    int rank = 0, size = 1, initialized = 0;
    MPI_Initialized(&initialized);  // tools without MPI build serially
    if (initialized) MPI_Comm_rank(comm, &rank), MPI_Comm_size(comm, &size);
    std::vector<int> all(static_cast<std::size_t>(m_.source_.size()));
    for (std::size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
    std::vector<Pending> level{{0, std::move(all)}};
    for (int depth = 0; !level.empty(); ++depth) {
      // 1. Classify: edges near the cell, a vertex near it, the side of its centre.
      std::vector<Cell> cells(level.size());
      std::vector<std::size_t> candidates;
      for (std::size_t i = 0; i < level.size(); ++i) {
        cells[i] = classify(level[i]);
        if (cells[i].candidate) candidates.push_back(i);
      }
      // 2. This rank's fits.
      std::vector<std::size_t> mine;
      for (std::size_t k = static_cast<std::size_t>(rank); k < candidates.size();
           k += static_cast<std::size_t>(size))
        mine.push_back(k);
      std::vector<Fit> fits(mine.size());
      const auto fit_mine = [&] {
        parallel_for(static_cast<Index>(mine.size()), 1, [&](Index first, Index last) {
          for (Index j = first; j < last; ++j) {
            const std::size_t i = candidates[mine[static_cast<std::size_t>(j)]];
            fits[static_cast<std::size_t>(j)] = fit(level[i].id, cells[i]);
          }
        });
      };
      if (size == 1)
        fit_mine();
      else
        run_collectively(comm, fit_mine);
      // 3. Every rank's fits: per fit [accepted, exact evaluations, worst f, worst J, coefficients if
      // accepted].
      std::vector<double> send;
      for (const Fit& f : fits) {
        send.insert(send.end(),
                    {f.accepted ? 1.0 : 0.0, static_cast<double>(f.evaluations), f.worst_f, f.worst_J});
        send.insert(send.end(), f.stored.begin(), f.stored.end());
      }
      std::vector<Fit> all_fits(candidates.size());
      if (size == 1) {
        for (std::size_t j = 0; j < fits.size(); ++j) all_fits[mine[j]] = std::move(fits[j]);
      } else {
        std::vector<int> counts(static_cast<std::size_t>(size)), displs(static_cast<std::size_t>(size), 0);
        const int count = static_cast<int>(send.size());
        require(send.size() < static_cast<std::size_t>(std::numeric_limits<int>::max()),
                "map interpolant: too many coefficients on one level to gather");
        MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
        long long total = 0;
        for (int r = 0; r < size; ++r)
          displs[static_cast<std::size_t>(r)] = static_cast<int>(total),
          total += counts[static_cast<std::size_t>(r)];
        require(total < std::numeric_limits<int>::max(),
                "map interpolant: too many coefficients on one level to gather");
        std::vector<double> received(static_cast<std::size_t>(total));
        MPI_Allgatherv(send.data(), count, MPI_DOUBLE, received.data(), counts.data(), displs.data(),
                       MPI_DOUBLE, comm);
        const std::size_t block = static_cast<std::size_t>(kComponents * n1_ * padded(n1_));
        for (int r = 0; r < size; ++r) {
          const double* in = received.data() + displs[static_cast<std::size_t>(r)];
          for (std::size_t k = static_cast<std::size_t>(r); k < candidates.size();
               k += static_cast<std::size_t>(size)) {
            Fit& f = all_fits[k];
            f.accepted = in[0] != 0;
            f.evaluations = static_cast<Index>(in[1]);
            f.worst_f = in[2];
            f.worst_J = in[3];
            in += 4;
            if (f.accepted) f.stored.assign(in, in + block), in += block;
          }
        }
      }
      // 4. Apply in the order of the level: leaves, or four children for the next level.
      std::vector<Pending> next;
      std::size_t k = 0;
      for (std::size_t i = 0; i < level.size(); ++i) {
        Cell& cell = cells[i];
        const int id = level[i].id;
        if (cell.outside) {
          ++m_.stats_.outside_leaves;
          continue;
        }
        if (cell.candidate) {
          Fit& f = all_fits[k++];
          m_.stats_.exact_evaluations += f.evaluations;
          if (f.accepted) {
            store(id, cell, f);
            continue;
          }
        }
        if (depth < o_.max_depth) {
          const Node node = m_.nodes_[static_cast<std::size_t>(id)];
          const int first = static_cast<int>(m_.nodes_.size());
          m_.nodes_[static_cast<std::size_t>(id)].child = first;
          const Real h = node.h / 2;
          for (int q = 0; q < 4; ++q) {
            m_.nodes_.push_back(Node{node.x0 + (q & 1) * h, node.y0 + (q >> 1) * h, h});
            next.push_back({first + q, cell.edges});
          }
          continue;
        }
        ++m_.stats_.exact_leaves;
        const Node& node = m_.nodes_[static_cast<std::size_t>(id)];
        m_.stats_.exact_area_fraction += node.h * node.h / (side_ * side_);
      }
      level = std::move(next);
    }
  }

 private:
  struct Pending {
    int id;
    std::vector<int> parent_edges;
  };
  struct Cell {
    std::vector<int> edges;  // of ∂Ω0 meeting the cell grown by its size
    bool outside = false, candidate = false, center_inside = true;
  };
  struct Fit {
    bool accepted = false;
    Index evaluations = 0;
    Real worst_f = 0, worst_J = 0;
    std::vector<Real> stored;  // the leaf's coefficients, if accepted
  };

  Cell classify(const Pending& p) const {
    const Node& node = m_.nodes_[static_cast<std::size_t>(p.id)];
    const Polygon& s = m_.source_;
    // f is singular at the vertices: a cell closer than its size to one would
    // converge slowly (and test points might miss its error peak), so it is
    // split (or left exact) without a fit. The edges kept are those meeting the
    // cell grown by that much (a superset of those meeting its children's grown cells).
    const Real reach = node.h;
    const Real x0 = node.x0 - reach, y0 = node.y0 - reach;
    const Real x1 = node.x0 + node.h + reach, y1 = node.y0 + node.h + reach;
    Cell cell;
    bool has_vertex = false;
    for (int e : p.parent_edges) {
      const Point<2>& a = s.vertex(e);
      if (!segment_meets_box(a, s.vertex(e + 1), x0, y0, x1, y1)) continue;
      cell.edges.push_back(e);
      has_vertex = has_vertex || (a.x() >= x0 && a.x() <= x1 && a.y() >= y0 && a.y() <= y1);
    }
    const Point<2> center(node.x0 + node.h / 2, node.y0 + node.h / 2);
    const int center_side = s.side_of(center);
    cell.outside = cell.edges.empty() && center_side < 0;
    cell.candidate = !cell.outside && !has_vertex && center_side != 0;
    cell.center_inside = center_side > 0;
    return cell;
  }

  // Makes node `id` an interpolated leaf with the accepted fit `f`.
  void store(int id, const Cell& c, const Fit& f) {
    Node& cell = m_.nodes_[static_cast<std::size_t>(id)];
    InterpolantStats& st = m_.stats_;
    st.max_f_error = std::max(st.max_f_error, f.worst_f);
    st.max_J_error = std::max(st.max_J_error, f.worst_J);
    ++st.interpolated_leaves;
    cell.kind = 1;
    cell.coefficients = m_.coefficients_.append(f.stored.data());
    // Evaluation tests inside/outside only against the edges that meet the cell
    // itself (grown by a margin far above rounding): the others can neither
    // cross the segment from the centre nor hold the point, so the parity is
    // the same, and most leaves near ∂Ω0 then need no test at all.
    cell.edges_begin = static_cast<int>(m_.edge_list_.size());
    cell.center_inside = c.center_inside;
    const Real margin = 1e-6 * cell.h;
    for (const int e : c.edges)
      if (segment_meets_box(m_.source_.vertex(e), m_.source_.vertex(e + 1), cell.x0 - margin,
                            cell.y0 - margin, cell.x0 + cell.h + margin, cell.y0 + cell.h + margin))
        m_.edge_list_.push_back(e);
    cell.edges_count = static_cast<int>(m_.edge_list_.size()) - cell.edges_begin;
  }

  // Fits the cell and tests the fit (reads the tree only: fits run in parallel).
  Fit fit(int id, const Cell& info) const {
    const Node& cell = m_.nodes_[static_cast<std::size_t>(id)];
    const std::vector<int>& edges = info.edges;
    Fit result;
    const Index nn = static_cast<Index>(n1_) * n1_;
    const Index nt = static_cast<Index>(tests_.size());
    Points<2> P(nn, 2), T(nt, 2);
    auto to_x = [&](Real u) { return cell.x0 + (u + 1) / 2 * cell.h; };
    auto to_y = [&](Real v) { return cell.y0 + (v + 1) / 2 * cell.h; };
    for (int l = 0; l < n1_; ++l)
      for (int k = 0; k < n1_; ++k) P.row(k + l * n1_) << to_x(nodes_u_[k]), to_y(nodes_u_[l]);
    for (Index t = 0; t < nt; ++t) T.row(t) << to_x(tests_[t].first), to_y(tests_[t].second);
    Points<2> X;
    Jacobians<2> J;
    m_.exact_->eval_with_jacobian(P, X, J);
    result.evaluations += nn;
    if (!X.allFinite() || !J.allFinite()) return result;

    std::vector<Real> C(static_cast<std::size_t>(kComponents * nn));
    const int stride = padded(n1_);
    std::vector<Real> stored(static_cast<std::size_t>(kComponents * n1_ * stride), 0.0);
    MatrixX F(n1_, n1_);
    for (int c = 0; c < kComponents; ++c) {
      for (int l = 0; l < n1_; ++l)
        for (int k = 0; k < n1_; ++k) F(k, l) = c < 2 ? X(k + l * n1_, c) : J(k + l * n1_, c - 2);
      const MatrixX Cc = M_ * F * M_.transpose();
      std::copy(Cc.data(), Cc.data() + nn, C.begin() + c * nn);
      for (int j = 0; j < n1_; ++j)
        for (int i = 0; i < n1_; ++i)
          stored[static_cast<std::size_t>(c * n1_ * stride + i + j * stride)] = Cc(i, j);
    }
    // The last Chebyshev coefficients estimate the error everywhere in the
    // cell; they reject most cells before the test points cost evaluations.
    Real small_J = std::numeric_limits<Real>::infinity();
    for (Index r = 0; r < nn; ++r) small_J = std::min(small_J, J.row(r).lpNorm<Eigen::Infinity>());
    for (int c = 0; c < kComponents; ++c) {
      Real tail = 0;  // the last row and column: a conservative estimate of the error
      for (int i = 0; i < n1_; ++i)
        tail += std::abs(C[c * nn + (n1_ - 1) + i * n1_]) + std::abs(C[c * nn + i + (n1_ - 1) * n1_]);
      if (tail > (c < 2 ? tol_f_ : tol_J_ * small_J) / 2) return result;
    }
    m_.exact_->eval_with_jacobian(T, X, J);
    result.evaluations += nt;
    Real worst_f = 0, worst_J = 0;
    for (Index t = 0; t < nt; ++t) {
      const Index r = t;
      if (!inside_by_parity(m_.source_, edges.data(), static_cast<int>(edges.size()), cell.x0 + cell.h / 2,
                            cell.y0 + cell.h / 2, info.center_inside, T(r, 0), T(r, 1)))
        continue;
      Real v[kComponents];
      evaluate_leaf_one(stored.data(), n1_, tests_[t].first, tests_[t].second, 0, kComponents, v);
      const Real ef = std::max(std::abs(v[0] - X(r, 0)), std::abs(v[1] - X(r, 1)));
      Real eJ = 0, sJ = 0;
      for (int c = 0; c < 4; ++c) {
        eJ = std::max(eJ, std::abs(v[2 + c] - J(r, c)));
        sJ = std::max(sJ, std::abs(J(r, c)));
      }
      // Half the tolerance: test points sample the error, they do not bound it.
      if (ef > tol_f_ / 2 || eJ > tol_J_ / 2 * sJ) return result;
      worst_f = std::max(worst_f, ef / diam_);
      worst_J = std::max(worst_J, eJ / sJ);
    }
    result.accepted = true;
    result.worst_f = worst_f;
    result.worst_J = worst_J;
    result.stored = std::move(stored);
    return result;
  }

  AdaptiveInterpolant& m_;
  const InterpolantOptions& o_;
  const int n1_;
  Real diam_ = 0, side_ = 0, tol_f_ = 0, tol_J_ = 0;
  MatrixX M_;  // values at the Chebyshev points → coefficients
  std::vector<Real> nodes_u_;
  std::vector<std::pair<Real, Real>> tests_;
};

Index AdaptiveInterpolant::LeafCoefficients::append(const Real* values) {
  if (count_ % kLeavesPerBlock == 0)
    blocks_.push_back(
        std::make_unique_for_overwrite<Real[]>(static_cast<std::size_t>(kLeavesPerBlock) * leaf_size_));
  std::copy_n(values, leaf_size_,
              blocks_.back().get() + static_cast<std::size_t>(count_ % kLeavesPerBlock) * leaf_size_);
  return count_++;
}

AdaptiveInterpolant::AdaptiveInterpolant(MapPtr<2> exact, const Polygon& source, InterpolantOptions options,
                                         MPI_Comm comm)
    : exact_(std::move(exact)), source_(source), options_(options) {
  if (!(options_.tolerance > 0) || options_.degree < 1 || options_.degree >= kMaxDegree ||
      options_.max_depth < 0 || options_.max_depth > 40 || options_.test_points < 0)
    throw Error(
        "map interpolant: the tolerance must be positive, the degree in [1, 30] and the depth in [0, 40]",
        {.file = "", .key_path = "map.interpolation_tolerance", .hint = "e.g. 1e-12"});
  coefficients_ = LeafCoefficients(
      static_cast<std::size_t>(kComponents * (options_.degree + 1) * padded(options_.degree + 1)));
  const Stopwatch watch;
  const double cpu = process_cpu_seconds();
  Builder(*this).build(comm);
  stats_.build_seconds = watch.seconds();
  stats_.build_cpu_seconds = process_cpu_seconds() - cpu;
  log::info("map interpolant: ", stats_.interpolated_leaves, " interpolated leaves (degree ", options_.degree,
            "), ", stats_.exact_leaves, " exact (", stats_.exact_area_fraction * 100,
            " % of the bounding square), ", stats_.exact_evaluations, " exact evaluations, built in ",
            format_seconds(stats_.build_seconds), " (CPU of this rank ",
            format_seconds(stats_.build_cpu_seconds), "); worst error at test points: f ", stats_.max_f_error,
            " · diam, J_f ", stats_.max_J_error, " relative");
}

int AdaptiveInterpolant::leaf_of(Real x, Real y) const {
  const Node& root = nodes_.front();
  if (!(x >= root.x0 && x <= root.x0 + root.h && y >= root.y0 && y <= root.y0 + root.h)) return -1;
  int id = 0;
  while (nodes_[static_cast<std::size_t>(id)].child >= 0) {
    const Node& n = nodes_[static_cast<std::size_t>(id)];
    const Real half = n.h / 2;
    id = n.child + (x >= n.x0 + half ? 1 : 0) + (y >= n.y0 + half ? 2 : 0);
  }
  return id;
}

bool AdaptiveInterpolant::inside(const Node& leaf, Real x, Real y) const {
  return inside_by_parity(source_, edge_list_.data() + leaf.edges_begin, leaf.edges_count,
                          leaf.x0 + leaf.h / 2, leaf.y0 + leaf.h / 2, leaf.center_inside, x, y);
}

void AdaptiveInterpolant::run(const Points<2>& x0, Points<2>* x, Jacobians<2>* J) const {
  const Index N = x0.rows();
  const int first = x ? 0 : 2, last = J ? 6 : 2;
  const int n1 = options_.degree + 1;
  const bool batched = n1 <= kMaxBatchedN1;
  // Read every input point before writing (x may alias x0); fallback points are written last.
  std::vector<char> fallback(static_cast<std::size_t>(N), 0);
  Points<2> out_x;
  Jacobians<2> out_J;
  Points<2>& X = x ? (x == &x0 ? out_x : *x) : out_x;
  Jacobians<2>& JJ = J ? *J : out_J;
  if (x) X.resize(N, 2);
  if (J) JJ.resize(N, 4);
  parallel_for(N, 4096, [&](Index begin, Index end) {
    // Consecutive points often share a leaf: a point well inside the last
    // leaf (by a margin far above the rounding of the cell bounds) is in it,
    // wherever the descent would put points on the cell's sides.
    const Node* last_leaf = nullptr;
    Real lo_x = 0, hi_x = -1, lo_y = 0, hi_y = -1;
    // Points of one leaf go through the batched kernel eight at a time.
    const auto put = [&](Index p, const Real* v, int stride) {
      if (x) X(p, 0) = v[0], X(p, 1) = v[stride];
      if (J)
        for (int c = 0; c < 4; ++c) JJ(p, c) = v[(c + 2 - first) * stride];
    };
    // A few batches stay open at once: the points of neighbouring cells
    // alternate between two or three leaves where leaves meet, and a single
    // open batch would be flushed half empty at every switch.
    struct Batch {
      alignas(64) Real u[kLanes];
      alignas(64) Real v[kLanes];
      Index p[kLanes];
      int count = 0;
      const Node* leaf = nullptr;
    };
    constexpr int kOpenBatches = 4;
    std::array<Batch, kOpenBatches> batches;
    alignas(64) Real res[kComponents * kLanes];
    const auto flush = [&](Batch& b) {
      if (b.count == 0) return;
      for (int l = b.count; l < kLanes; ++l) b.u[l] = b.u[b.count - 1], b.v[l] = b.v[b.count - 1];
      evaluate_leaf8(coefficients_[b.leaf->coefficients], n1, b.u, b.v, first, last, res);
      for (int l = 0; l < b.count; ++l) put(b.p[l], res + l, kLanes);
      b.count = 0;
      b.leaf = nullptr;
    };
    // The open batch of `leaf`, or a free one, or the fullest one flushed.
    const auto batch_for = [&](const Node* leaf) -> Batch& {
      Batch* chosen = nullptr;
      for (Batch& b : batches) {
        if (b.leaf == leaf) return b;
        if (!chosen || (chosen->count > 0 && (b.count == 0 || b.count > chosen->count))) chosen = &b;
      }
      flush(*chosen);
      chosen->leaf = leaf;
      return *chosen;
    };
    for (Index p = begin; p < end; ++p) {
      const Real px = x0(p, 0), py = x0(p, 1);
      const Node* leaf = last_leaf;
      if (!(px > lo_x && px < hi_x && py > lo_y && py < hi_y)) {
        const int id = leaf_of(px, py);
        leaf = id < 0 ? nullptr : &nodes_[static_cast<std::size_t>(id)];
        if (leaf) {
          const Real margin = 1e-9 * leaf->h;
          last_leaf = leaf;
          lo_x = leaf->x0 + margin, hi_x = leaf->x0 + leaf->h - margin;
          lo_y = leaf->y0 + margin, hi_y = leaf->y0 + leaf->h - margin;
        }
      }
      if (!leaf || leaf->kind == 0 || (leaf->edges_count > 0 && !inside(*leaf, px, py))) {
        fallback[static_cast<std::size_t>(p)] = 1;
        continue;
      }
      const Real u = 2 * (px - leaf->x0) / leaf->h - 1, w = 2 * (py - leaf->y0) / leaf->h - 1;
      if (!batched) {
        Real v[kComponents];
        evaluate_leaf(coefficients_[leaf->coefficients], n1, u, w, first, last, v);
        put(p, v, 1);
        continue;
      }
      Batch& b = batch_for(leaf);
      b.u[b.count] = u, b.v[b.count] = w, b.p[b.count] = p;
      if (++b.count == kLanes) flush(b);
    }
    for (Batch& b : batches) flush(b);
  });
  std::vector<Index> rest;
  for (Index p = 0; p < N; ++p)
    if (fallback[static_cast<std::size_t>(p)]) rest.push_back(p);
  if (!rest.empty()) {
    Points<2> sub(static_cast<Index>(rest.size()), 2), sx;
    Jacobians<2> sJ;
    for (std::size_t k = 0; k < rest.size(); ++k) sub.row(static_cast<Index>(k)) = x0.row(rest[k]);
    if (x && J)
      exact_->eval_with_jacobian(sub, sx, sJ);
    else if (x)
      exact_->eval(sub, sx);
    else
      exact_->jacobian(sub, sJ);
    for (std::size_t k = 0; k < rest.size(); ++k) {
      if (x) X.row(rest[k]) = sx.row(static_cast<Index>(k));
      if (J) JJ.row(rest[k]) = sJ.row(static_cast<Index>(k));
    }
  }
  if (x == &x0) *x = std::move(out_x);
}

void AdaptiveInterpolant::eval(const Points<2>& x0, Points<2>& x) const {
  run(x0, &x, nullptr);
}

void AdaptiveInterpolant::jacobian(const Points<2>& x0, Jacobians<2>& J) const {
  run(x0, nullptr, &J);
}

void AdaptiveInterpolant::eval_with_jacobian(const Points<2>& x0, Points<2>& x, Jacobians<2>& J) const {
  run(x0, &x, &J);
}

std::string AdaptiveInterpolant::describe() const {
  std::ostringstream os;
  os << exact_->describe() << ", interpolated (" << stats_.interpolated_leaves << " leaves of degree "
     << options_.degree << ", tolerance " << options_.tolerance << ")";
  return os.str();
}

}  // namespace warpfem::mapping
