#include "fem/postprocessing/output_mesh.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/mesh/polygon_triangulation.hpp"
#include "core/prefault.hpp"
#include "core/threads.hpp"
#include "core/timer.hpp"
#include "fem/geometry/warped_geometry.hpp"
#include "fem/postprocessing/fold_check.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

namespace {

// x = f(x0) and det J_f at x0, in chunks: the Jacobians of all nodes at once
// would be the largest array of the output.
template <int dim>
void warp_in_chunks(const mapping::Map<dim>& map, const Points<dim>& x0, Points<dim>& x, VectorX& det) {
  const Index n = x0.rows();
  x.resize(n, dim);
  det.resize(n);
  prefault(x.data(), static_cast<std::size_t>(n * dim) * sizeof(double));
  prefault(det.data(), static_cast<std::size_t>(n) * sizeof(double));
  constexpr Index chunk = Index{1} << 16;
  for (Index first = 0; first < n; first += chunk) {
    const Index count = std::min(chunk, n - first);
    VectorX chunk_det;
    x.middleRows(first, count) = warp_nodes(map, Points<dim>(x0.middleRows(first, count)), &chunk_det);
    det.segment(first, count) = chunk_det;
  }
}

// v = n copies of `value`, its pages populated in one call (large fresh arrays).
template <class T>
void filled(std::vector<T>& v, std::size_t n, T value) {
  v.clear();
  resize_prefaulted(v, n);
  std::fill(v.begin(), v.end(), value);
}

// The edges of the local cells, each once: per smaller vertex number, the
// sorted larger vertex numbers of its edges (a compressed row, searched
// linearly: a vertex has a handful of edges). Edges are numbered by their
// place in these rows, from 0 to size() − 1 without gaps.
class LocalEdges {
 public:
  LocalEdges() = default;
  template <int dim>
  LocalEdges(const Mesh<dim>& mesh, const std::vector<Index>& cells) {
    const auto& edges = cell_edges(mesh.cell_type);
    const auto nv = static_cast<std::size_t>(mesh.num_vertices());
    std::vector<Index> first;  // rows with repeats: each edge once per cell holding it
    filled(first, nv + 1, Index{0});
    for (const Index c : cells)
      for (const auto& e : edges)
        ++first[static_cast<std::size_t>(std::min(mesh.cells(c, e[0]), mesh.cells(c, e[1]))) + 1];
    for (std::size_t i = 1; i < first.size(); ++i) first[i] += first[i - 1];
    std::vector<TableIndex> count;
    resize_prefaulted(other_, static_cast<std::size_t>(first.back()));
    filled(count, nv, TableIndex{0});
    for (const Index c : cells)
      for (const auto& e : edges) {
        const TableIndex p = mesh.cells(c, e[0]), q = mesh.cells(c, e[1]);
        const auto a = static_cast<std::size_t>(std::min(p, q));
        other_[static_cast<std::size_t>(first[a] + count[a]++)] = std::max(p, q);
      }
    // Each row sorted, its repeats dropped, and moved left onto the rows before
    // it (start_[a] <= first[a], so no row is overwritten before it is read).
    filled(start_, nv + 1, Index{0});
    for (std::size_t a = 0; a < nv; ++a) {
      const auto row = other_.begin() + first[a];
      std::sort(row, row + count[a]);
      const auto end = std::unique(row, row + count[a]);
      if (start_[a] < first[a]) std::copy(row, end, other_.begin() + start_[a]);
      start_[a + 1] = start_[a] + (end - row);
    }
    other_.resize(static_cast<std::size_t>(start_.back()));
  }
  Index size() const { return static_cast<Index>(other_.size()); }
  Index index(TableIndex p, TableIndex q) const {
    const auto a = static_cast<std::size_t>(std::min(p, q));
    const TableIndex b = std::max(p, q);
    for (Index j = start_[a]; j < start_[a + 1]; ++j)
      if (other_[static_cast<std::size_t>(j)] == b) return j;
    throw Error("make_output_mesh: an edge of a local cell is missing from the edge table");
  }

 private:
  std::vector<Index> start_;
  std::vector<TableIndex> other_;
};

// A sub-region of mesh cell `cell_index` (index into the local cells), given
// by its vertices in that cell's reference coordinates.
struct Region {
  Index cell_index;
  std::array<Point<2>, 4> xi;
};

// Key of a node by its exact reference position in a mesh cell: subdivision
// points are dyadic, so children find their parent's and siblings' nodes.
struct XiKey {
  Index cell_index;
  std::uint64_t a, b;
  bool operator==(const XiKey&) const = default;
};
struct XiKeyHash {
  std::size_t operator()(const XiKey& k) const {
    return std::hash<Index>()(k.cell_index) ^ (std::hash<std::uint64_t>()(k.a) * 0x9E3779B97F4A7C15ULL) ^
           (std::hash<std::uint64_t>()(k.b) * 0xC2B2AE3D27D4EB4FULL);
  }
};
XiKey xi_key(Index cell_index, const Point<2>& xi) {
  XiKey k{cell_index, 0, 0};
  const double x = xi(0) + 0.0, y = xi(1) + 0.0;  // + 0.0 folds -0 into 0
  std::memcpy(&k.a, &x, sizeof x);
  std::memcpy(&k.b, &y, sizeof y);
  return k;
}

// The four pieces a folded region is split into: triangles at their edge
// midpoints, quadrilaterals at their edge midpoints and centre; all keep the
// parent's orientation.
std::vector<Region> split(const Region& r, CellType type) {
  const auto mid = [](const Point<2>& p, const Point<2>& q) -> Point<2> { return 0.5 * (p + q); };
  const auto& v = r.xi;
  const Index c = r.cell_index;
  if (type == CellType::triangle) {
    const Point<2> none = Point<2>::Zero();
    const Point<2> m01 = mid(v[0], v[1]), m12 = mid(v[1], v[2]), m20 = mid(v[2], v[0]);
    return {{c, {v[0], m01, m20, none}},
            {c, {m01, v[1], m12, none}},
            {c, {m20, m12, v[2], none}},
            {c, {m12, m20, m01, none}}};
  }
  const Point<2> centre = 0.25 * (v[0] + v[1] + v[2] + v[3]);
  std::vector<Region> out;
  for (std::size_t k = 0; k < 4; ++k)
    out.push_back({c, {v[k], mid(v[k], v[(k + 1) % 4]), centre, mid(v[(k + 3) % 4], v[k])}});
  return out;
}

// The rows of `cells` that hold every node, as compressed rows: the holders
// of node n are holders[start[n] .. start[n+1]).
std::pair<std::vector<Index>, std::vector<Index>> node_holders(const IndexTable& cells, Index npoints) {
  const Index ncells = cells.rows(), nloc = cells.cols();
  std::vector<Index> start(static_cast<std::size_t>(npoints) + 1, 0);
  for (Index c = 0; c < ncells; ++c)
    for (Index k = 0; k < nloc; ++k) ++start[static_cast<std::size_t>(cells(c, k)) + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<Index> holders(static_cast<std::size_t>(start.back()));
  std::vector<Index> fill(start.begin(), start.end() - 1);
  for (Index c = 0; c < ncells; ++c)
    for (Index k = 0; k < nloc; ++k)
      holders[static_cast<std::size_t>(fill[static_cast<std::size_t>(cells(c, k))]++)] = c;
  return {std::move(start), std::move(holders)};
}

// Calls visit(c) once for every row c of the node_holders table `rows` that
// holds one of `nodes`; `seen` has one entry per row.
template <class Visit>
void for_rows_holding(const std::vector<Index>& nodes,
                      const std::pair<std::vector<Index>, std::vector<Index>>& rows, std::vector<char>& seen,
                      const Visit& visit) {
  const auto& [start, holders] = rows;
  std::fill(seen.begin(), seen.end(), 0);
  for (const Index node : nodes)
    for (Index j = start[static_cast<std::size_t>(node)]; j < start[static_cast<std::size_t>(node) + 1];
         ++j) {
      const Index c = holders[static_cast<std::size_t>(j)];
      if (seen[static_cast<std::size_t>(c)]) continue;
      seen[static_cast<std::size_t>(c)] = 1;
      visit(c);
    }
}

// Cells whose curved geometry still folds — at a vertex where f is not
// differentiable the quadratic interpolant of f folds at any subdivision
// depth — get their non-vertex nodes pulled toward the straight cell spanned by
// their mapped vertices: x = c + t (f(x0) − c), with c the node's place on that
// straight cell and t halved, down to 0, until no cell holding a pulled node
// folds. Shared nodes move for every cell that holds them, so no crack opens;
// `frozen` nodes (on edges and faces another rank's cells share, whose copies
// there would not move) stay put. The field values stay those at x0.
template <int dim, class Tangled>
std::vector<Index> straighten_folded_cells(OutputMesh<dim>& out, const MatrixX& geometry, int nvert,
                                           const Tangled& tangled, std::vector<Index> folded,
                                           const std::vector<char>& frozen) {
  const Index ncells = out.cells.rows(), nloc = out.cells.cols(), npoints = out.points.rows();
  const auto row = [&](Index c) {
    std::vector<Index> nodes(static_cast<std::size_t>(nloc));
    for (Index k = 0; k < nloc; ++k) nodes[static_cast<std::size_t>(k)] = out.cells(c, k);
    return nodes;
  };
  std::vector<Index> work = std::move(folded);
  std::vector<char> folded_before(static_cast<std::size_t>(ncells), 0);
  for (const Index c : work) folded_before[static_cast<std::size_t>(c)] = 1;
  out.num_tangled_cells = static_cast<Index>(work.size());
  if (work.empty()) return {};
  const auto node_cells = node_holders(out.cells, npoints);
  const std::vector<Index>&start = node_cells.first, &holders = node_cells.second;
  const Points<dim> curved = out.points;
  std::vector<double> t(static_cast<std::size_t>(npoints), 1.0);
  std::unordered_map<Index, Point<dim>> straight;  // node -> its place on the straight cell
  std::vector<char> straightened(static_cast<std::size_t>(ncells), 0),
      seen(static_cast<std::size_t>(ncells), 0);
  constexpr std::array<double, 4> pull = {0.5, 0.25, 0.125, 0.0};
  for (std::size_t round = 0; round < pull.size() && !work.empty(); ++round) {
    std::vector<Index> moved;
    for (const Index c : work) {
      straightened[static_cast<std::size_t>(c)] = 1;
      for (Index k = nvert; k < nloc; ++k) {
        const Index node = out.cells(c, k);
        if (static_cast<std::size_t>(node) < frozen.size() && frozen[static_cast<std::size_t>(node)])
          continue;
        auto [it, inserted] = straight.try_emplace(node, Point<dim>::Zero());
        if (inserted)
          for (int v = 0; v < nvert; ++v)
            it->second += geometry(k, v) * curved.row(out.cells(c, v)).transpose();
        if (t[static_cast<std::size_t>(node)] > pull[round]) {
          t[static_cast<std::size_t>(node)] = pull[round];
          out.points.row(node) =
              (it->second + pull[round] * (curved.row(node).transpose() - it->second)).transpose();
          moved.push_back(node);
        }
      }
    }
    std::vector<Index> next;
    for_rows_holding(moved, node_cells, seen, [&](Index c) {
      if (tangled(row(c))) next.push_back(c);
    });
    work = std::move(next);
  }

  // Where f bends too strongly at the cells' scale, straight cells fold too and
  // the pulls can leave more folded cells than they found: those are undone.
  // Cells sharing a pulled node form one group and are decided together (a
  // group holds every cell of its pulled nodes, so groups are independent).
  std::vector<Index> group(static_cast<std::size_t>(ncells));
  std::iota(group.begin(), group.end(), Index{0});
  const auto root = [&](Index c) {
    while (group[static_cast<std::size_t>(c)] != c)
      c = group[static_cast<std::size_t>(c)] =
          group[static_cast<std::size_t>(group[static_cast<std::size_t>(c)])];
    return c;
  };
  const auto pulled = [&](Index node) { return t[static_cast<std::size_t>(node)] < 1; };
  for (Index node = 0; node < npoints; ++node) {
    if (!pulled(node)) continue;
    const Index first = root(holders[static_cast<std::size_t>(start[static_cast<std::size_t>(node)])]);
    for (Index j = start[static_cast<std::size_t>(node)] + 1; j < start[static_cast<std::size_t>(node) + 1];
         ++j)
      if (const Index r = root(holders[static_cast<std::size_t>(j)]); r != first)
        group[static_cast<std::size_t>(r)] = first;
  }
  std::vector<Index> before(static_cast<std::size_t>(ncells), 0), after(static_cast<std::size_t>(ncells), 0);
  std::vector<char> folded_after(folded_before);
  for (Index c = 0; c < ncells; ++c) {
    bool touched = false;
    for (Index k = nvert; k < nloc && !touched; ++k) touched = pulled(out.cells(c, k));
    if (touched) folded_after[static_cast<std::size_t>(c)] = tangled(row(c)) ? 1 : 0;
    before[static_cast<std::size_t>(root(c))] += folded_before[static_cast<std::size_t>(c)];
    after[static_cast<std::size_t>(root(c))] += folded_after[static_cast<std::size_t>(c)];
  }
  const auto undone = [&](Index c) {
    const Index r = root(c);
    return after[static_cast<std::size_t>(r)] >= before[static_cast<std::size_t>(r)];
  };
  for (Index node = 0; node < npoints; ++node)
    if (pulled(node) && undone(holders[static_cast<std::size_t>(start[static_cast<std::size_t>(node)])]))
      out.points.row(node) = curved.row(node);
  out.num_straightened_cells = 0;
  std::vector<Index> still;
  for (Index c = 0; c < ncells; ++c) {
    const bool keep = !undone(c);
    out.num_straightened_cells += keep && straightened[static_cast<std::size_t>(c)] ? 1 : 0;
    if ((keep ? folded_after : folded_before)[static_cast<std::size_t>(c)]) still.push_back(c);
  }
  out.num_tangled_cells = static_cast<Index>(still.size());
  return still;
}

// A point of the straight pieces that replace a folded output cell: its
// reference point in the mesh cell, f and det J_f there, and its output node
// (−1 until written).
template <int dim>
struct PiecePoint {
  Point<dim> xi, x;
  Index node = -1;
  double det = std::numeric_limits<double>::quiet_NaN();
};
template <int dim>
using Simplex = std::array<int, dim + 1>;

// Orientation (det of the edge vectors) of the image of simplex t of `points`.
template <int dim>
double image_orientation(const std::vector<PiecePoint<dim>>& points, const Simplex<dim>& t) {
  Matrix<dim> edges;
  for (int d = 0; d < dim; ++d)
    edges.col(d) = points[static_cast<std::size_t>(t[static_cast<std::size_t>(d + 1)])].x -
                   points[static_cast<std::size_t>(t[0])].x;
  return edges.determinant();
}

// The longest edge of simplex t of `points` in reference coordinates.
template <int dim>
double longest_reference_edge(const std::vector<PiecePoint<dim>>& points, const Simplex<dim>& t) {
  double longest = 0;
  for (std::size_t i = 0; i <= dim; ++i)
    for (std::size_t j = i + 1; j <= dim; ++j)
      longest = std::max(
          longest,
          (points[static_cast<std::size_t>(t[j])].xi - points[static_cast<std::size_t>(t[i])].xi).norm());
  return longest;
}

// Positive straight pieces cut corners where f bends: a piece spanning most
// of the angle f sweeps around a corner fills only part of its image. A piece
// with an edge longer than `coarse` of the reference cell whose image leaves
// its chord by more than `bend` of the chord's length (at the edge midpoint)
// is bisected at the most bent such edge whose halves both stay positive (if
// none, the piece stays whole), within a budget of pieces per cell. `pieces`
// is replaced by the result; midpoints are shared through `midpoint_of`, as
// in the bisection.
template <int dim, class Place>
void follow_bends(std::vector<PiecePoint<dim>>& points, std::vector<Simplex<dim>>& pieces, const Place& place,
                  std::map<std::pair<int, int>, int>& midpoint_of) {
  constexpr double coarse = 1.0 / 8, bend = 0.05;
  const std::size_t max_pieces = std::max<std::size_t>(4 * pieces.size(), dim == 2 ? 256 : 4096);
  const auto at = [&](int i) -> PiecePoint<dim>& { return points[static_cast<std::size_t>(i)]; };
  const auto orient = [&](const Simplex<dim>& t) { return image_orientation(points, t); };
  const auto reference_size = [&](const Simplex<dim>& t) { return longest_reference_edge(points, t); };
  const auto midpoint = [&](int a, int b) { return midpoint_of.at({std::min(a, b), std::max(a, b)}); };
  std::vector<Simplex<dim>> done, pending;
  for (const auto& t : pieces) (reference_size(t) > coarse ? pending : done).push_back(t);
  while (!pending.empty()) {
    // The edge midpoints of the pending pieces, placed by f in one batch.
    std::vector<int> fresh;
    for (const auto& t : pending)
      for (std::size_t i = 0; i <= dim; ++i)
        for (std::size_t j = i + 1; j <= dim; ++j) {
          const int a = t[i], b = t[j];
          const auto [it, inserted] =
              midpoint_of.try_emplace({std::min(a, b), std::max(a, b)}, static_cast<int>(points.size()));
          if (inserted) {
            points.push_back({0.5 * (at(a).xi + at(b).xi), Point<dim>::Zero(), -1});
            fresh.push_back(it->second);
          }
        }
    if (!fresh.empty()) place(points, fresh);
    std::vector<Simplex<dim>> next;
    for (const auto& t : pending) {
      if (done.size() + 2 * pending.size() > max_pieces) {  // the budget: the rest stays as it is
        done.push_back(t);
        continue;
      }
      // The bent edges, most bent first; the first whose halves both stay
      // positive is split.
      std::vector<std::pair<double, std::array<std::size_t, 2>>> bent;
      for (std::size_t i = 0; i <= dim; ++i)
        for (std::size_t j = i + 1; j <= dim; ++j) {
          const PiecePoint<dim>&a = at(t[i]), &b = at(t[j]);
          const double chord = (b.x - a.x).norm();
          const double off = (at(midpoint(t[i], t[j])).x - 0.5 * (a.x + b.x)).norm();
          if (off > bend * chord && (at(t[j]).xi - at(t[i]).xi).norm() > coarse)
            bent.push_back({off / chord, {i, j}});
        }
      std::sort(bent.begin(), bent.end(), [](const auto& p, const auto& q) { return p.first > q.first; });
      bool split = false;
      for (const auto& [ratio, edge] : bent) {
        const int m = midpoint(t[edge[0]], t[edge[1]]);
        Simplex<dim> first = t, second = t;  // the midpoint in place of either end keeps the orientation
        first[edge[1]] = m;
        second[edge[0]] = m;
        if (!(orient(first) > 0 && orient(second) > 0)) continue;
        for (const auto& half : {first, second})
          (reference_size(half) > coarse ? next : done).push_back(half);
        split = true;
        break;
      }
      if (!split) done.push_back(t);
    }
    pending.swap(next);
  }
  pieces.swap(done);
}

// The straight pieces bisect_until_positive writes over a folded output
// cell, and the tiny ones it leaves out (their reference volume as a
// fraction of the reference cell's).
template <int dim>
struct Bisection {
  std::vector<Simplex<dim>> pieces;
  Index left_out = 0;
  double left_out_volume = 0;
};

// Straight simplices placed by f over a folded output cell, for where f opens
// a corner or edge of Ω1: next to it f can sweep most of the corner's angle
// over a sliver of a cell, at every scale, so no curved cell and no regular
// subdivision follows it. Starting from `pending` (simplices of `points`,
// positively oriented in the reference cell), a piece whose mapped vertices
// are not positively oriented is bisected at the midpoint of its edge with
// the longest image (across the sweep). Midpoints are shared by the pieces on
// both sides of an edge; `place` maps the reference points of new points to
// Ω1 (one batch per round).
// Next to a point where f is not differentiable (where the boundary map of a
// 3D cage kinks, f sweeps alike at every scale) some pieces stay folded at
// every depth, but their region shrinks with each bisection: a piece still
// folded when all its edges are below `tiny` of the reference cell is left
// out of the output (a hole far below what any rendering resolves; counted).
// Returns no pieces if one is still folded at the depth limit or the pieces
// exceed their budget (then the cell is written as it was). With `bends`, the
// positive pieces then follow f's bends (follow_bends).
template <int dim, class Place>
Bisection<dim> bisect_until_positive(std::vector<PiecePoint<dim>>& points, std::vector<Simplex<dim>> pending,
                                     const Place& place, bool bends = false) {
  constexpr int max_depth = 40 * dim;
  constexpr std::size_t max_pieces = 20000;
  constexpr double tiny = 1e-6;
  const auto at = [&](int i) -> PiecePoint<dim>& { return points[static_cast<std::size_t>(i)]; };
  const auto orient = [&](const Simplex<dim>& t) { return image_orientation(points, t); };
  const auto reference_size = [&](const Simplex<dim>& t) { return longest_reference_edge(points, t); };
  std::map<std::pair<int, int>, int> midpoint_of;
  Bisection<dim> result;
  for (int depth = 0; !pending.empty(); ++depth) {
    std::vector<Simplex<dim>> next;
    std::vector<int> fresh;
    for (const auto& t : pending) {
      if (orient(t) > 0) {
        result.pieces.push_back(t);
        continue;
      }
      if (reference_size(t) < tiny) {
        Matrix<dim> edges;
        for (int d = 0; d < dim; ++d) edges.col(d) = at(t[static_cast<std::size_t>(d + 1)]).xi - at(t[0]).xi;
        ++result.left_out;
        result.left_out_volume += std::abs(edges.determinant());  // the reference simplex has det 1
        continue;
      }
      if (depth == max_depth || result.pieces.size() + 2 * pending.size() > max_pieces) return {};
      std::size_t i_long = 0, j_long = 1;
      double length = -1;
      for (std::size_t i = 0; i <= dim; ++i)
        for (std::size_t j = i + 1; j <= dim; ++j)
          if (const double l = (at(t[j]).x - at(t[i]).x).norm(); l > length)
            length = l, i_long = i, j_long = j;
      const int a = t[i_long], b = t[j_long];
      const auto [it, inserted] =
          midpoint_of.try_emplace({std::min(a, b), std::max(a, b)}, static_cast<int>(points.size()));
      if (inserted) {
        points.push_back({0.5 * (at(a).xi + at(b).xi), Point<dim>::Zero(), -1});
        fresh.push_back(it->second);
      }
      // The midpoint in place of either end keeps the orientation.
      Simplex<dim> first = t, second = t;
      first[j_long] = it->second;
      second[i_long] = it->second;
      next.push_back(first);
      next.push_back(second);
    }
    if (!fresh.empty()) place(points, fresh);
    pending.swap(next);
  }
  if (bends) follow_bends(points, result.pieces, place, midpoint_of);
  return result;
}

// Ω0 positions of reference points xi.row(j), each in mesh cell cell_of(j)
// (the cell's straight geometry).
template <int dim, class CellOf>
Points<dim> omega0_points(const Mesh<dim>& mesh, const Points<dim>& xi, const CellOf& cell_of) {
  const MatrixX weights = LagrangeElement<dim>(mesh.cell_type, 1).values(xi);
  Points<dim> x0(xi.rows(), dim);
  for (Index j = 0; j < xi.rows(); ++j) {
    const Index cell = cell_of(j);
    Point<dim> x = Point<dim>::Zero();
    for (Index v = 0; v < weights.cols(); ++v) x += weights(j, v) * mesh.vertex(mesh.cells(cell, v));
    x0.row(j) = x.transpose();
  }
  return x0;
}

// Ω0 positions of reference points of mesh cell `cell`.
template <int dim>
Points<dim> cell_points(const Mesh<dim>& mesh, Index cell, const Points<dim>& xi) {
  return omega0_points(mesh, xi, [cell](Index) { return cell; });
}

// f and det J_f at the reference points `fresh` of `points` in mesh cell `cell`.
template <int dim>
auto placer(const Mesh<dim>& mesh, const mapping::Map<dim>& map, Index cell) {
  return [&mesh, &map, cell](std::vector<PiecePoint<dim>>& points, const std::vector<int>& fresh) {
    Points<dim> xi(static_cast<Index>(fresh.size()), dim);
    for (std::size_t j = 0; j < fresh.size(); ++j)
      xi.row(static_cast<Index>(j)) = points[static_cast<std::size_t>(fresh[j])].xi.transpose();
    VectorX det;
    const Points<dim> x1 = warp_nodes(map, cell_points(mesh, cell, xi), &det);
    for (std::size_t j = 0; j < fresh.size(); ++j) {
      PiecePoint<dim>& p = points[static_cast<std::size_t>(fresh[j])];
      p.x = x1.row(static_cast<Index>(j)).transpose();
      p.det = det(static_cast<Index>(j));
    }
  };
}

// det J_f at the rows of `x0` whose entry of `det` is still NaN (the nodes
// not placed by f: midpoints of straight piece edges).
template <int dim>
void fill_missing_det(const mapping::Map<dim>& map, const Points<dim>& x0, VectorX& det) {
  std::vector<Index> missing;
  for (Index j = 0; j < det.size(); ++j)
    if (std::isnan(det(j))) missing.push_back(j);
  if (missing.empty()) return;
  Points<dim> at(static_cast<Index>(missing.size()), dim);
  for (std::size_t k = 0; k < missing.size(); ++k) at.row(static_cast<Index>(k)) = x0.row(missing[k]);
  VectorX found;
  warp_nodes(map, at, &found);
  for (std::size_t k = 0; k < missing.size(); ++k) det(missing[k]) = found(static_cast<Index>(k));
}

// Appends output nodes: their Ω0 positions x0, det J_f, and their positions
// in Ω1 from `nodes` (anything with a member x, in the same order).
template <int dim, class Node>
void append_output_nodes(OutputMesh<dim>& out, const Points<dim>& x0, const std::vector<Node>& nodes,
                         const VectorX& det) {
  const Index first = out.points.rows(), n = x0.rows();
  out.reference_points.conservativeResize(first + n, dim);
  out.points.conservativeResize(first + n, dim);
  out.map_det.conservativeResize(first + n);
  out.reference_points.bottomRows(n) = x0;
  for (Index j = 0; j < n; ++j) out.points.row(first + j) = nodes[static_cast<std::size_t>(j)].x.transpose();
  out.map_det.tail(n) = det;
}

// Quadratic triangles and tetrahedra that still fold after subdivision and
// straightening are replaced by straight pieces (bisect_until_positive),
// their edge nodes on the chords: the first in the row's place, the others
// appended. Hanging nodes and the boundary follow f, not the neighbours'
// quadratic edges and faces (untangled, not watertight). A row with a piece
// still negative at the depth limit stays as it was. `corner(row, v)` is the
// reference point of the row's vertex v in its mesh cell. Returns the rows
// replaced.
template <int dim, class Corner>
Index cut_folded_simplices(OutputMesh<dim>& out, const Mesh<dim>& mesh, const mapping::Map<dim>& map,
                           const Corner& corner, const std::vector<Index>& rows,
                           std::vector<std::pair<Index, Point<dim>>>& added_sources) {
  const auto& edges = cell_edges(mesh.cell_type);
  const Index nloc = out.cells.cols();
  Index replaced = 0;
  for (const Index r : rows) {
    const Index cell = out.cell_ids[static_cast<std::size_t>(r)];
    std::vector<PiecePoint<dim>> points;
    Simplex<dim> whole;
    for (int v = 0; v <= dim; ++v) {
      points.push_back({corner(r, v), out.points.row(out.cells(r, v)).transpose(), out.cells(r, v)});
      whole[static_cast<std::size_t>(v)] = v;
    }
    const Bisection<dim> bisection = bisect_until_positive<dim>(points, {whole}, placer(mesh, map, cell));
    const auto& pieces = bisection.pieces;
    if (pieces.empty()) continue;
    out.num_left_out_pieces += bisection.left_out;
    out.left_out_volume += bisection.left_out_volume;
    // New nodes: the pieces' vertices placed by f, and their edge midpoints
    // (straight edges; their det J_f is found below).
    std::vector<PiecePoint<dim>> fresh;
    const Index first_new = out.points.rows();
    const auto new_node = [&](const PiecePoint<dim>& p) {
      fresh.push_back(p);
      return first_new + static_cast<Index>(fresh.size()) - 1;
    };
    std::map<std::pair<int, int>, Index> edge_node;
    std::vector<std::vector<Index>> rows_out;
    for (const auto& t : pieces) {
      std::vector<Index> row;
      for (const int p : t) {
        PiecePoint<dim>& q = points[static_cast<std::size_t>(p)];
        if (q.node < 0) q.node = new_node(q);
        row.push_back(q.node);
      }
      for (const auto& e : edges) {
        const int a = t[static_cast<std::size_t>(e[0])], b = t[static_cast<std::size_t>(e[1])];
        const auto [it, inserted] = edge_node.try_emplace({std::min(a, b), std::max(a, b)}, 0);
        if (inserted) {
          const PiecePoint<dim>&p = points[static_cast<std::size_t>(a)],
                &q = points[static_cast<std::size_t>(b)];
          it->second = new_node({0.5 * (p.xi + q.xi), 0.5 * (p.x + q.x)});
        }
        row.push_back(it->second);
      }
      rows_out.push_back(std::move(row));
    }
    const Index nfresh = static_cast<Index>(fresh.size());
    Points<dim> xi(nfresh, dim);
    VectorX det(nfresh);
    for (Index j = 0; j < nfresh; ++j) {
      const PiecePoint<dim>& p = fresh[static_cast<std::size_t>(j)];
      xi.row(j) = p.xi.transpose();
      det(j) = p.det;
      added_sources.emplace_back(out.source_cells[static_cast<std::size_t>(r)], p.xi);
    }
    const Points<dim> x0 = cell_points(mesh, cell, xi);
    fill_missing_det(map, x0, det);
    append_output_nodes(out, x0, fresh, det);
    const Index old_rows = out.cells.rows(), extra = static_cast<Index>(rows_out.size()) - 1;
    out.cells.conservativeResize(old_rows + extra, nloc);
    for (std::size_t p = 0; p < rows_out.size(); ++p) {
      const Index row = p == 0 ? r : old_rows + static_cast<Index>(p) - 1;
      for (Index k = 0; k < nloc; ++k)
        out.cells(row, k) = static_cast<TableIndex>(rows_out[p][static_cast<std::size_t>(k)]);
      if (p > 0) {
        out.cell_ids.push_back(out.cell_ids[static_cast<std::size_t>(r)]);
        out.source_cells.push_back(out.source_cells[static_cast<std::size_t>(r)]);
      }
    }
    ++replaced;
  }
  return replaced;
}

// Quadratic hexahedra that still fold after the pulls toward straight cells
// (where f opens an edge of Ω0 into a reflex one, the mapped vertices of a
// cell along it span no hexahedron, and even the straight trilinear cell
// folds) are written as straight tetrahedra placed by f: the six of the
// cell's Kuhn subdivision (around its diagonal from vertex 0 to vertex 6),
// bisected until each is positive (bisect_until_positive), their edge nodes
// on the chords. They follow f, not the neighbours' curved faces (untangled,
// not watertight). The rows cut move from `cells` to `simplex_cells`; the
// added nodes' sources are appended to `added_sources` in node order.
// Returns how many of `rows` stay folded.
Index write_folded_hexahedra_as_tetrahedra(OutputMesh<3>& out, const Mesh<3>& mesh,
                                           const mapping::Map<3>& map, const std::vector<Index>& rows,
                                           std::vector<std::pair<Index, Point<3>>>& added_sources) {
  const LagrangeElement<3> linear(CellType::hexahedron, 1);
  const auto& tet_edges = cell_edges(CellType::tetrahedron);
  constexpr std::array<Simplex<3>, 6> kuhn = {
      {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}}};
  const Index nrows = out.cells.rows();
  std::vector<PiecePoint<3>> added;  // new nodes, with the row that added them
  std::vector<Index> added_row;
  std::vector<std::array<Index, 10>> tets;  // node ids, or −(1 + index into `added`)
  std::vector<Index> tet_rows;
  std::vector<char> replaced(static_cast<std::size_t>(nrows), 0);
  Index left_folded = 0;
  for (const Index r : rows) {
    std::vector<PiecePoint<3>> points;
    for (int v = 0; v < 8; ++v)
      points.push_back(
          {linear.nodes().row(v).transpose(), out.points.row(out.cells(r, v)).transpose(), out.cells(r, v)});
    std::vector<Simplex<3>> start;
    for (Simplex<3> t : kuhn) {
      Matrix<3> edges;
      for (int d = 0; d < 3; ++d)
        edges.col(d) = points[static_cast<std::size_t>(t[static_cast<std::size_t>(d + 1)])].xi -
                       points[static_cast<std::size_t>(t[0])].xi;
      if (edges.determinant() < 0) std::swap(t[1], t[2]);
      start.push_back(t);
    }
    const Bisection<3> bisection =
        bisect_until_positive<3>(points, start, placer(mesh, map, out.cell_ids[static_cast<std::size_t>(r)]),
                                 /*bends=*/true);
    if (bisection.pieces.empty()) {
      ++left_folded;
      continue;
    }
    out.num_left_out_pieces += bisection.left_out;
    out.left_out_volume += bisection.left_out_volume / 6;  // the reference cube holds six unit tetrahedra
    const auto new_node = [&](const PiecePoint<3>& p) {
      added.push_back(p);
      added_row.push_back(r);
      return -static_cast<Index>(added.size());
    };
    // Nodes only for the points the pieces use (the bend refinement also
    // placed midpoints of edges it did not split).
    std::vector<Index> created(points.size(), 0);  // added nodes are numbered −1, −2, …
    const auto node_of = [&](int i) {
      const PiecePoint<3>& p = points[static_cast<std::size_t>(i)];
      if (p.node >= 0) return p.node;
      Index& c = created[static_cast<std::size_t>(i)];
      if (c == 0) c = new_node(p);
      return c;
    };
    std::map<std::pair<int, int>, Index> middle;
    for (const auto& t : bisection.pieces) {
      std::array<Index, 10> row{};
      for (std::size_t v = 0; v < 4; ++v) row[v] = node_of(t[v]);
      for (std::size_t e = 0; e < tet_edges.size(); ++e) {
        const int a = t[static_cast<std::size_t>(tet_edges[e][0])],
                  b = t[static_cast<std::size_t>(tet_edges[e][1])];
        const auto [it, inserted] = middle.try_emplace({std::min(a, b), std::max(a, b)}, 0);
        if (inserted) {
          const PiecePoint<3>&p = points[static_cast<std::size_t>(a)],
                &q = points[static_cast<std::size_t>(b)];
          it->second = new_node({0.5 * (p.xi + q.xi), 0.5 * (p.x + q.x)});
        }
        row[4 + e] = it->second;
      }
      tets.push_back(row);
      tet_rows.push_back(r);
    }
    replaced[static_cast<std::size_t>(r)] = 1;
  }
  if (tets.empty()) return left_folded;

  // The added nodes: Ω0 position by the mesh cell's geometry, det J_f by f.
  const Index nadded = static_cast<Index>(added.size()), first_new = out.points.rows();
  Points<3> xi(nadded, 3);
  VectorX det(nadded);
  for (Index j = 0; j < nadded; ++j) {
    const PiecePoint<3>& a = added[static_cast<std::size_t>(j)];
    xi.row(j) = a.xi.transpose();
    det(j) = a.det;
    added_sources.emplace_back(
        out.source_cells[static_cast<std::size_t>(added_row[static_cast<std::size_t>(j)])], a.xi);
  }
  const Points<3> x0 = omega0_points(mesh, xi, [&](Index j) {
    return out.cell_ids[static_cast<std::size_t>(added_row[static_cast<std::size_t>(j)])];
  });
  fill_missing_det(map, x0, det);
  append_output_nodes(out, x0, added, det);

  // Rows: the hexahedra kept, then the tetrahedra (VTK order: corners, then
  // the nodes of edges 01, 12, 02, 03, 13, 23).
  const Index nreplaced = static_cast<Index>(std::count(replaced.begin(), replaced.end(), 1));
  IndexTable kept(nrows - nreplaced, out.cells.cols()), table(static_cast<Index>(tets.size()), 10);
  std::vector<Index> ids, sources;
  for (Index r = 0, q = 0; r < nrows; ++r)
    if (!replaced[static_cast<std::size_t>(r)]) {
      kept.row(q++) = out.cells.row(r);
      ids.push_back(out.cell_ids[static_cast<std::size_t>(r)]);
      sources.push_back(out.source_cells[static_cast<std::size_t>(r)]);
    }
  for (std::size_t t = 0; t < tets.size(); ++t) {
    for (int k = 0; k < 10; ++k) {
      const Index n = tets[t][static_cast<std::size_t>(k)];
      table(static_cast<Index>(t), k) = static_cast<TableIndex>(n >= 0 ? n : first_new + (-n - 1));
    }
    ids.push_back(out.cell_ids[static_cast<std::size_t>(tet_rows[t])]);
    sources.push_back(out.source_cells[static_cast<std::size_t>(tet_rows[t])]);
  }
  out.cells = std::move(kept);
  out.simplex_cells = std::move(table);
  out.cell_ids = std::move(ids);
  out.source_cells = std::move(sources);
  out.num_split_cells += nreplaced;
  return left_folded;
}

// Quadratic quadrilaterals that fold even as straight cells: where f opens a
// corner of Ω0 into a reflex corner of Ω1, the mapped vertices of a cell at
// that corner form a non-convex quadrilateral, and no bilinear cell over them
// is untangled at any size. Each is cut along the diagonal that leaves two
// positively oriented triangles (straight along the diagonal). A triangle
// that folds with its curved cell edges gets those edges straight (its edge
// nodes move onto the segment between its mapped vertices, for the
// neighbours sharing them too, which are checked again and cut in turn if
// that folds them); a straight triangle with positive vertices never folds.
// Starts from the rows `folded`. Returns per row the diagonal cut (0: vertices
// 0–2, 1: vertices 1–3) or −1; `uncut` flags the folded rows no diagonal cuts
// into two positive triangles. `frozen` edge nodes (shared with another rank)
// never move.
template <class Tangled>
std::vector<int> cut_folded_quadrilaterals(OutputMesh<2>& out, const Tangled& tangled,
                                           const std::vector<char>& frozen, const std::vector<Index>& folded,
                                           std::vector<char>& uncut) {
  const Index ncells = out.cells.rows();
  std::vector<int> diagonal(static_cast<std::size_t>(ncells), -1);
  uncut.assign(static_cast<std::size_t>(ncells), 0);
  const auto row = [&](Index c) {
    std::vector<Index> nodes(static_cast<std::size_t>(out.cells.cols()));
    for (Index k = 0; k < out.cells.cols(); ++k) nodes[static_cast<std::size_t>(k)] = out.cells(c, k);
    return nodes;
  };
  std::vector<Index> work = folded;
  if (work.empty()) return diagonal;
  const auto node_cells = node_holders(out.cells, out.points.rows());
  // Node k of a row's boundary ring: vertex k/2 for even k, else the node of edge k/2.
  const auto ring = [&](Index c, int k) { return out.cells(c, k % 8 % 2 == 0 ? k % 8 / 2 : 4 + k % 8 / 2); };
  const auto at = [&](Index node) -> Point<2> { return out.points.row(node).transpose(); };
  const auto orientation = [](const Point<2>& a, const Point<2>& b, const Point<2>& c) {
    return (b(0) - a(0)) * (c(1) - a(1)) - (b(1) - a(1)) * (c(0) - a(0));
  };
  const auto is_frozen = [&](Index node) {
    return static_cast<std::size_t>(node) < frozen.size() && frozen[static_cast<std::size_t>(node)];
  };
  const FoldCheck<2> triangle_check(LagrangeElement<2>(CellType::triangle, 2));
  // Triangle t (0, 1) of cut row c: ring nodes a, a+2, a+4 (t = 0) or a+4, a+6, a
  // (t = 1) with a = 2 × diagonal, and the straight diagonal's midpoint.
  const auto first_ring = [&](Index c, int t) { return 2 * diagonal[static_cast<std::size_t>(c)] + 4 * t; };
  const auto triangle_folds = [&](Index c, int t) {
    const int a = first_ring(c, t);
    std::array<Point<2>, FoldCheck<2>::max_nodes> x;
    x[0] = at(ring(c, a)), x[1] = at(ring(c, a + 2)), x[2] = at(ring(c, a + 4));
    x[3] = at(ring(c, a + 1)), x[4] = at(ring(c, a + 3)), x[5] = 0.5 * (x[0] + x[2]);
    return triangle_check.folds(x.data());
  };
  const auto cut_folds = [&](Index c) { return triangle_folds(c, 0) || triangle_folds(c, 1); };
  std::vector<char> seen(static_cast<std::size_t>(ncells), 0);
  while (!work.empty()) {
    std::vector<Index> moved;
    for (const Index c : work) {
      if (diagonal[static_cast<std::size_t>(c)] < 0) {
        const Point<2> p0 = at(out.cells(c, 0)), p1 = at(out.cells(c, 1)), p2 = at(out.cells(c, 2)),
                       p3 = at(out.cells(c, 3));
        const double along02 = std::min(orientation(p0, p1, p2), orientation(p0, p2, p3));
        const double along13 = std::min(orientation(p0, p1, p3), orientation(p1, p2, p3));
        if (!(std::max(along02, along13) > 0)) {  // not even a simple, positive quadrilateral
          uncut[static_cast<std::size_t>(c)] = 1;
          continue;
        }
        diagonal[static_cast<std::size_t>(c)] = along02 >= along13 ? 0 : 1;
      }
      for (int t = 0; t < 2; ++t) {
        if (!triangle_folds(c, t)) continue;
        const int a = first_ring(c, t);
        for (const int k : {a + 1, a + 3}) {  // the triangle's cell edges, straight
          const Index node = ring(c, k);
          const Point<2> straight = 0.5 * (at(ring(c, k - 1)) + at(ring(c, k + 1)));
          if (is_frozen(node) || at(node) == straight) continue;
          out.points.row(node) = straight.transpose();
          moved.push_back(node);
        }
      }
    }
    // Rows holding a moved node: cut them (again) if that folds them.
    std::vector<Index> next;
    for_rows_holding(moved, node_cells, seen, [&](Index c) {
      if (diagonal[static_cast<std::size_t>(c)] >= 0 ? cut_folds(c) : tangled(row(c))) next.push_back(c);
    });
    work = std::move(next);
  }
  return diagonal;
}

// Writes the quadrilaterals that fold even as straight cells as quadratic
// triangles (OutputMesh::simplex_cells). First cut_folded_quadrilaterals: two
// triangles per cell, conforming with its neighbours. A cell that no diagonal cuts into two positive
// triangles (its mapped vertices cross: f turns so sharply inside it that only
// its curved edges stay apart) is triangulated over its eight mapped boundary
// nodes by CGAL, when they form a simple polygon; its boundary is then the
// polyline through its edge nodes, which the neighbours' curved edges pass
// through too. Nodes are added at the midpoints of triangle edges that are no
// cell edge (on the straight edge; the field value is the FE function's at
// the corresponding reference point). `row_corners` holds the reference
// corners of every row in its mesh cell, or is empty when every row is a
// whole cell.
template <class Tangled>
void write_folded_quadrilaterals_as_triangles(OutputMesh<2>& out, const Mesh<2>& mesh,
                                              const mapping::Map<2>& map, const Tangled& tangled,
                                              const std::vector<char>& frozen,
                                              std::vector<std::array<Point<2>, 4>>& row_corners,
                                              std::vector<Index>& folded,
                                              std::vector<std::pair<Index, Point<2>>>& added_sources) {
  std::vector<char> uncut;
  const std::vector<int> diagonal = cut_folded_quadrilaterals(out, tangled, frozen, folded, uncut);
  const Index nrows = out.cells.rows();
  const auto& edges = cell_edges(CellType::quadrilateral);
  const LagrangeElement<2> linear(CellType::quadrilateral, 1);
  std::array<Point<2>, 4> whole{};
  for (int v = 0; v < 4; ++v) whole[static_cast<std::size_t>(v)] = linear.nodes().row(v).transpose();
  const auto row_nodes = [&](Index r) {
    std::vector<Index> nodes(9);
    for (int k = 0; k < 9; ++k) nodes[static_cast<std::size_t>(k)] = out.cells(r, k);
    return nodes;
  };
  // Boundary nodes of a row in counter-clockwise order (vertex, edge node, ...)
  // as output node, position and reference point.
  struct BoundaryNode {
    Index node;
    Point<2> x, xi;
    double det = std::numeric_limits<double>::quiet_NaN();  // det J_f, if f placed the node
  };
  const auto boundary = [&](Index r) {
    const auto& corners = row_corners.empty() ? whole : row_corners[static_cast<std::size_t>(r)];
    std::vector<BoundaryNode> ring;
    for (int v = 0; v < 4; ++v) {
      const auto& e = edges[static_cast<std::size_t>(v)];
      ring.push_back({out.cells(r, v), out.points.row(out.cells(r, v)).transpose(),
                      corners[static_cast<std::size_t>(v)]});
      ring.push_back(
          {out.cells(r, 4 + v), out.points.row(out.cells(r, 4 + v)).transpose(),
           0.5 * (corners[static_cast<std::size_t>(e[0])] + corners[static_cast<std::size_t>(e[1])])});
    }
    return ring;
  };

  // The triangles, as rows of boundary nodes plus per edge either an existing
  // node or the index of a node to add.
  struct NewNode {
    Index row;
    Point<2> xi, x;
    double det = std::numeric_limits<double>::quiet_NaN();  // det J_f, if f placed the node
  };
  std::vector<NewNode> added;
  std::vector<std::array<Index, 6>> triangles;  // existing node ids, or -(1 + added index)
  std::vector<Index> triangle_rows;
  std::vector<char> replaced(static_cast<std::size_t>(nrows), 0);
  const auto midpoint = [&](Index r, const BoundaryNode& a, const BoundaryNode& b) {
    added.push_back({r, 0.5 * (a.xi + b.xi), 0.5 * (a.x + b.x)});
    return -static_cast<Index>(added.size());
  };
  // The triangles of CGAL's triangulation of a row's boundary ring, when the
  // ring is a simple counter-clockwise polygon; a node is added at the
  // midpoint of each triangle edge (ring edges are pieces of a cell edge).
  const auto triangulate = [&](Index r, const std::vector<BoundaryNode>& ring) {
    std::vector<Point<2>> polygon;
    for (const auto& b : ring) polygon.push_back(b.x);
    const auto pieces = triangulate_simple_polygon(polygon);
    for (const auto& t : pieces) {
      std::array<Index, 6> row{};
      for (int k = 0; k < 3; ++k) {
        const auto& a = ring[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
        const auto& b = ring[static_cast<std::size_t>(t[static_cast<std::size_t>((k + 1) % 3)])];
        row[static_cast<std::size_t>(k)] = a.node;
        row[static_cast<std::size_t>(3 + k)] = midpoint(r, a, b);
      }
      triangles.push_back(row);
      triangle_rows.push_back(r);
    }
    return !pieces.empty();
  };
  std::vector<Index> fine_rows;
  for (Index r = 0; r < nrows; ++r) {
    const int d = diagonal[static_cast<std::size_t>(r)];
    const std::vector<BoundaryNode> ring = boundary(r);
    const auto at = [&](int k) -> const BoundaryNode& { return ring[static_cast<std::size_t>(k % 8)]; };
    if (d >= 0) {
      // Vertices 2d, 2d + 2, 2d + 4 and 2d + 4, 2d + 6, 2d of the ring.
      const int a = 2 * d;
      const Index mid = midpoint(r, at(a), at(a + 4));
      triangles.push_back({at(a).node, at(a + 2).node, at(a + 4).node, at(a + 1).node, at(a + 3).node, mid});
      triangles.push_back({at(a + 4).node, at(a + 6).node, at(a).node, at(a + 5).node, at(a + 7).node, mid});
      triangle_rows.insert(triangle_rows.end(), 2, r);
      replaced[static_cast<std::size_t>(r)] = 1;
      continue;
    }
    if (!uncut[static_cast<std::size_t>(r)] || !tangled(row_nodes(r))) continue;
    if (triangulate(r, ring))
      replaced[static_cast<std::size_t>(r)] = 1;
    else
      fine_rows.push_back(r);
  }
  // Rows whose eight boundary nodes cross: their boundary again with more
  // nodes per edge placed by f (4, then 16 intervals per edge), which follows
  // f's sharp turn closely enough in most cases.
  for (const int intervals : {4, 16}) {
    if (fine_rows.empty()) break;
    const Index nfine = static_cast<Index>(fine_rows.size()), per_row = 4 * (intervals - 2);
    Points<2> xi(per_row * nfine, 2);
    for (Index f = 0; f < nfine; ++f) {
      const auto ring = boundary(fine_rows[static_cast<std::size_t>(f)]);
      Index j = per_row * f;
      for (int e = 0; e < 4; ++e)
        for (int i = 1; i < intervals; ++i) {
          if (2 * i == intervals) continue;  // the edge node
          const Point<2>&a = ring[static_cast<std::size_t>(2 * e)].xi,
                &b = ring[static_cast<std::size_t>((2 * e + 2) % 8)].xi;
          xi.row(j++) = (a + (static_cast<double>(i) / intervals) * (b - a)).transpose();
        }
    }
    VectorX det;
    const Points<2> x1 = warp_nodes(
        map,
        omega0_points(
            mesh, xi,
            [&](Index j) {
              return out.cell_ids[static_cast<std::size_t>(fine_rows[static_cast<std::size_t>(j / per_row)])];
            }),
        &det);
    std::vector<Index> still;
    for (Index f = 0; f < nfine; ++f) {
      const Index r = fine_rows[static_cast<std::size_t>(f)];
      const auto coarse = boundary(r);
      std::vector<BoundaryNode> ring;
      Index j = per_row * f;
      for (int e = 0; e < 4; ++e)
        for (int i = 0; i < intervals; ++i) {
          if (i == 0 || 2 * i == intervals) {
            ring.push_back(coarse[static_cast<std::size_t>(2 * e + (i == 0 ? 0 : 1))]);
          } else {  // numbered below, once the ring is known to be simple
            ring.push_back(
                {std::numeric_limits<Index>::max(), x1.row(j).transpose(), xi.row(j).transpose(), det(j)});
            ++j;
          }
        }
      std::vector<Point<2>> polygon;
      for (const auto& b : ring) polygon.push_back(b.x);
      if (triangulate_simple_polygon(polygon).empty()) {
        still.push_back(r);
        continue;
      }
      for (auto& b : ring)
        if (b.node == std::numeric_limits<Index>::max()) {
          added.push_back({r, b.xi, b.x, b.det});
          b.node = -static_cast<Index>(added.size());
        }
      triangulate(r, ring);
      replaced[static_cast<std::size_t>(r)] = 1;
    }
    fine_rows = std::move(still);
  }
  // Rows whose boundary ring still crosses (next to a vertex of Ω1 where f
  // opens a corner): straight pieces placed by f (bisect_until_positive),
  // from the row's two triangles along diagonal 0–2.
  for (const Index r : fine_rows) {
    const auto& corners = row_corners.empty() ? whole : row_corners[static_cast<std::size_t>(r)];
    std::vector<PiecePoint<2>> points;
    for (int v = 0; v < 4; ++v)
      points.push_back({corners[static_cast<std::size_t>(v)], out.points.row(out.cells(r, v)).transpose(),
                        out.cells(r, v)});
    const Bisection<2> bisection = bisect_until_positive<2>(
        points, {{0, 1, 2}, {0, 2, 3}}, placer(mesh, map, out.cell_ids[static_cast<std::size_t>(r)]));
    const auto& pieces = bisection.pieces;
    if (pieces.empty()) continue;
    out.num_left_out_pieces += bisection.left_out;
    out.left_out_volume += bisection.left_out_volume / 2;  // the reference square has twice the area
    std::map<std::pair<int, int>, Index> middle;
    const auto mid = [&](int a, int b) {
      const auto [it, inserted] = middle.try_emplace({std::min(a, b), std::max(a, b)}, 0);
      if (inserted) {
        const PiecePoint<2>&p = points[static_cast<std::size_t>(a)], &q = points[static_cast<std::size_t>(b)];
        added.push_back({r, 0.5 * (p.xi + q.xi), 0.5 * (p.x + q.x)});
        it->second = -static_cast<Index>(added.size());
      }
      return it->second;
    };
    // Nodes only for the points the pieces use; added nodes are numbered −1, −2, ….
    std::vector<Index> created(points.size(), 0);
    const auto node = [&](int i) {
      const PiecePoint<2>& p = points[static_cast<std::size_t>(i)];
      if (p.node >= 0) return p.node;
      Index& c = created[static_cast<std::size_t>(i)];
      if (c == 0) {
        added.push_back({r, p.xi, p.x, p.det});
        c = -static_cast<Index>(added.size());
      }
      return c;
    };
    for (const auto& [a, b, c] : pieces) {
      triangles.push_back({node(a), node(b), node(c), mid(a, b), mid(b, c), mid(c, a)});
      triangle_rows.push_back(r);
    }
    replaced[static_cast<std::size_t>(r)] = 1;
  }
  if (triangles.empty()) return;

  // The added nodes: Ω0 position by the mesh cell's geometry, det J_f by f.
  const Index nadded = static_cast<Index>(added.size());
  Points<2> xi(nadded, 2);
  VectorX det(nadded);
  for (Index j = 0; j < nadded; ++j) {
    const NewNode& a = added[static_cast<std::size_t>(j)];
    xi.row(j) = a.xi.transpose();
    det(j) = a.det;
    added_sources.emplace_back(out.source_cells[static_cast<std::size_t>(a.row)], a.xi);
  }
  const Points<2> x0 = omega0_points(mesh, xi, [&](Index j) {
    return out.cell_ids[static_cast<std::size_t>(added[static_cast<std::size_t>(j)].row)];
  });
  fill_missing_det(map, x0, det);
  const Index first_new = out.points.rows();
  append_output_nodes(out, x0, added, det);

  // Rows: the quadrilaterals kept, then the triangles of an earlier call, then
  // the new triangles (VTK order: corners, then the nodes of edges 01, 12, 20).
  const Index nreplaced = static_cast<Index>(std::count(replaced.begin(), replaced.end(), 1));
  const Index nold = out.simplex_cells.rows();
  IndexTable quads(nrows - nreplaced, 9), table(nold + static_cast<Index>(triangles.size()), 6);
  std::vector<Index> ids, sources;
  std::vector<std::array<Point<2>, 4>> corners_kept;
  folded.clear();  // rows of `quads` still folded: uncut and not triangulated
  for (Index r = 0, q = 0; r < nrows; ++r)
    if (!replaced[static_cast<std::size_t>(r)]) {
      if (uncut[static_cast<std::size_t>(r)] && tangled(row_nodes(r))) folded.push_back(q);
      quads.row(q++) = out.cells.row(r);
      ids.push_back(out.cell_ids[static_cast<std::size_t>(r)]);
      sources.push_back(out.source_cells[static_cast<std::size_t>(r)]);
      if (!row_corners.empty()) corners_kept.push_back(row_corners[static_cast<std::size_t>(r)]);
    }
  table.topRows(nold) = out.simplex_cells;
  for (Index t = 0; t < nold; ++t) {
    ids.push_back(out.cell_ids[static_cast<std::size_t>(nrows + t)]);
    sources.push_back(out.source_cells[static_cast<std::size_t>(nrows + t)]);
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 6; ++k) {
      const Index n = triangles[t][static_cast<std::size_t>(k)];
      table(nold + static_cast<Index>(t), k) = static_cast<TableIndex>(n >= 0 ? n : first_new + (-n - 1));
    }
    ids.push_back(out.cell_ids[static_cast<std::size_t>(triangle_rows[t])]);
    sources.push_back(out.source_cells[static_cast<std::size_t>(triangle_rows[t])]);
  }
  out.cells = std::move(quads);
  out.simplex_cells = std::move(table);
  out.cell_ids = std::move(ids);
  out.source_cells = std::move(sources);
  if (!row_corners.empty()) row_corners = std::move(corners_kept);
  out.num_split_cells += nreplaced;
}

// Written triangles (OutputMesh::simplex_cells) whose geometry folds.
Index folded_triangles(const OutputMesh<2>& out) {
  const FoldCheck<2> check(LagrangeElement<2>(CellType::triangle, 2));
  Index count = 0;
  for (Index r = 0; r < out.simplex_cells.rows(); ++r) {
    std::array<Point<2>, FoldCheck<2>::max_nodes> x;
    for (int k = 0; k < 6; ++k)
      x[static_cast<std::size_t>(k)] = out.points.row(out.simplex_cells(r, k)).transpose();
    count += check.folds(x.data()) ? 1 : 0;
  }
  return count;
}

}  // namespace

template <int dim>
OutputMesh<dim> make_output_mesh(const Mesh<dim>& mesh, const DofDistribution<dim>& dist,
                                 const mapping::Map<dim>& map, int order) {
  Stopwatch watch;
  double cpu = process_cpu_seconds();
  OutputMesh<dim> out;
  out.cell_type = mesh.cell_type;
  out.order = order;
  const LagrangeElement<dim> element(mesh.cell_type, order);
  require(element.dofs_per_edge() <= 1, "make_output_mesh: output order " + std::to_string(order) +
                                            " is not supported (at most one node per edge)");
  const int nloc = element.num_dofs(), nvert = element.num_vertex_dofs();
  const auto& edges = cell_edges(mesh.cell_type);
  const int edge_nodes_end = nvert + static_cast<int>(edges.size()) * element.dofs_per_edge();
  const int face_nodes_end =
      edge_nodes_end +
      (dim == 3 ? static_cast<int>(cell_faces(mesh.cell_type).size()) : 0) * element.dofs_per_face();
  const LagrangeElement<dim> linear(mesh.cell_type, 1);
  // Node positions in Ω0: the straight cell geometry at the element's nodes.
  const MatrixX geometry = linear.values(element.nodes());  // nodes x vertices
  const auto& cells = dist.local_cells();
  const Index ncells = static_cast<Index>(cells.size());
  out.cells.resize(ncells, nloc);
  prefault(out.cells.data(), static_cast<std::size_t>(out.cells.size()) * sizeof(TableIndex));
  out.cell_ids = cells;
  out.source_cells.resize(cells.size());
  std::iota(out.source_cells.begin(), out.source_cells.end(), Index{0});
  // Vertices of other ranks' cells: edge and face nodes among them are never
  // pulled (straighten_folded_cells), since each rank decides its pulls alone.
  // A rank that holds every cell has none.
  std::vector<char> foreign;
  if (mesh.partial || ncells < mesh.num_cells()) {
    std::vector<char> local(static_cast<std::size_t>(mesh.num_cells()), 0);
    for (const Index c : cells) local[static_cast<std::size_t>(c)] = 1;
    // A partial level stores only the cells of its present ranges.
    const std::vector<std::array<Index, 2>> stored =
        mesh.partial ? mesh.present_cells : std::vector<std::array<Index, 2>>{{0, mesh.num_cells()}};
    for (const auto& [first, last] : stored)
      for (Index c = first; c < last; ++c)
        if (!local[static_cast<std::size_t>(c)]) {
          if (foreign.empty()) foreign.assign(static_cast<std::size_t>(mesh.num_vertices()), 0);
          for (int v = 0; v < nvert; ++v) foreign[static_cast<std::size_t>(mesh.cells(c, v))] = 1;
        }
  }
  // Nodes the local cells share are numbered without a search: first the
  // vertices of the local cells (in the mesh's order), then their edges
  // (LocalEdges' order), then face nodes (Q2 hexahedra, by their face's sorted
  // vertex numbers) and interior nodes in the order the cells first reach
  // them. No mesh-wide numbering of edges or faces is used, so the output of a
  // level stored only around this rank's cells works too.
  std::vector<TableIndex> vertex_node;
  filled(vertex_node, static_cast<std::size_t>(mesh.num_vertices()), TableIndex{-1});
  for (const Index c : cells)
    for (int v = 0; v < nvert; ++v) vertex_node[static_cast<std::size_t>(mesh.cells(c, v))] = 0;
  Index n = 0;
  for (TableIndex& node : vertex_node)
    if (node == 0) node = static_cast<TableIndex>(n++);
  const Index num_vertex_nodes = n;
  const LocalEdges local_edges = edge_nodes_end > nvert ? LocalEdges(mesh, cells) : LocalEdges();
  n += local_edges.size();
  require(n < std::numeric_limits<TableIndex>::max(), "make_output_mesh: too many output nodes on one rank");
  parallel_for(ncells, 1 << 14, [&](Index first, Index last) {
    for (Index i = first; i < last; ++i) {
      const Index c = cells[static_cast<std::size_t>(i)];
      for (int v = 0; v < nvert; ++v)
        out.cells(i, v) = vertex_node[static_cast<std::size_t>(mesh.cells(c, v))];
      for (int k = nvert; k < edge_nodes_end; ++k) {
        const auto& e = edges[static_cast<std::size_t>(k - nvert)];
        out.cells(i, k) = static_cast<TableIndex>(
            num_vertex_nodes + local_edges.index(mesh.cells(c, e[0]), mesh.cells(c, e[1])));
      }
    }
  });
  std::vector<TableIndex>().swap(vertex_node);
  if (nloc > edge_nodes_end) {
    using FaceKey = std::array<Index, 4>;
    struct FaceKeyHash {
      std::size_t operator()(const FaceKey& k) const {
        std::size_t h = std::hash<Index>()(k[0]);
        for (std::size_t i = 1; i < k.size(); ++i)
          h ^= std::hash<Index>()(k[i]) * (0xC2B2AE3D27D4EB4FULL * i);
        return h;
      }
    };
    std::unordered_map<FaceKey, TableIndex, FaceKeyHash> face_node;
    for (Index i = 0; i < ncells; ++i) {
      const Index c = cells[static_cast<std::size_t>(i)];
      for (int k = edge_nodes_end; k < nloc; ++k) {
        TableIndex* slot = nullptr;
        if constexpr (dim == 3)
          if (k < face_nodes_end) {
            const auto& f = cell_faces(mesh.cell_type)[static_cast<std::size_t>(k - edge_nodes_end)];
            FaceKey key;
            key.fill(-1);
            for (std::size_t j = 0; j < f.size(); ++j) key[j] = mesh.cells(c, f[j]);
            for (std::size_t a = 1; a < f.size(); ++a)  // sorted: insertion into at most four
              for (std::size_t b = a; b > 0 && key[b - 1] > key[b]; --b) std::swap(key[b - 1], key[b]);
            slot = &face_node.try_emplace(key, -1).first->second;
          }
        if (slot && *slot >= 0) {
          out.cells(i, k) = *slot;
          continue;
        }
        require(n < std::numeric_limits<TableIndex>::max(),
                "make_output_mesh: too many output nodes on one rank");
        out.cells(i, k) = static_cast<TableIndex>(n++);
        if (slot) *slot = out.cells(i, k);
      }
    }
  }
  // Every node's source, the first local cell that reaches it (cells visited
  // last to first, so the first one writes last).
  resize_prefaulted(out.node_in_cell_, static_cast<std::size_t>(n));
  for (Index i = ncells - 1; i >= 0; --i) {
    const Index c = cells[static_cast<std::size_t>(i)];
    for (int k = 0; k < nloc; ++k)
      out.node_in_cell_[static_cast<std::size_t>(out.cells(i, k))] = c * nloc + k;
  }
  // Positions in Ω0 by the straight geometry of that cell.
  out.reference_points.resize(n, dim);
  prefault(out.reference_points.data(), static_cast<std::size_t>(n * dim) * sizeof(double));
  std::vector<char> frozen;  // per node
  if (!foreign.empty()) filled(frozen, static_cast<std::size_t>(n), char{0});
  parallel_for(n, 1 << 14, [&](Index first, Index last) {
    for (Index node = first; node < last; ++node) {
      const Index code = out.node_in_cell_[static_cast<std::size_t>(node)];
      const Index c = code / nloc;
      const int k = static_cast<int>(code % nloc);
      Point<dim> x = Point<dim>::Zero();
      for (int v = 0; v < nvert; ++v) x += geometry(k, v) * mesh.vertex(mesh.cells(c, v));
      out.reference_points.row(node) = x.transpose();
      if (!foreign.empty() && k >= nvert && k < face_nodes_end) {
        bool shared = true;  // every vertex of the node's edge or face is a foreign one
        if (k < edge_nodes_end) {
          for (const int v : edges[static_cast<std::size_t>(k - nvert)])
            shared = shared && foreign[static_cast<std::size_t>(mesh.cells(c, v))];
        } else if constexpr (dim == 3) {
          for (const int v : cell_faces(mesh.cell_type)[static_cast<std::size_t>(k - edge_nodes_end)])
            shared = shared && foreign[static_cast<std::size_t>(mesh.cells(c, v))];
        }
        frozen[static_cast<std::size_t>(node)] = shared ? 1 : 0;
      }
    }
  });
  log::debug("output mesh: ", n, " nodes numbered in ", format_seconds(watch.seconds()), " (CPU ",
             format_seconds(process_cpu_seconds() - cpu), ")");
  watch.reset();
  cpu = process_cpu_seconds();
  warp_in_chunks(map, out.reference_points, out.points, out.map_det);
  log::debug("output mesh: nodes placed by the map in ", format_seconds(watch.seconds()), " (CPU ",
             format_seconds(process_cpu_seconds() - cpu), ")");
  watch.reset();
  cpu = process_cpu_seconds();
  out.num_mesh_cells = ncells;

  // The quadratic interpolant of f can fold a cell even where det J_f > 0 (a
  // strongly curved cell near a reentrant vertex of Ω1): in 2D such cells are
  // replaced by four children whose nodes are again placed by f, recursively.
  const FoldCheck<dim> fold_check(element);
  const auto tangled = [&](const std::vector<Index>& nodes) {
    std::array<Point<dim>, FoldCheck<dim>::max_nodes> x;
    for (int k = 0; k < nloc; ++k)
      x[static_cast<std::size_t>(k)] = out.points.row(nodes[static_cast<std::size_t>(k)]).transpose();
    return fold_check.folds(x.data());
  };
  // The cells as numbered: checked in parallel, each independently.
  std::vector<char> folded_cell(static_cast<std::size_t>(ncells), 0);
  parallel_for(ncells, 1024, [&](Index first, Index last) {
    std::array<Point<dim>, FoldCheck<dim>::max_nodes> x;
    for (Index i = first; i < last; ++i) {
      for (int k = 0; k < nloc; ++k)
        x[static_cast<std::size_t>(k)] = out.points.row(out.cells(i, k)).transpose();
      folded_cell[static_cast<std::size_t>(i)] = fold_check.folds(x.data()) ? 1 : 0;
    }
  });
  std::vector<Index> folded;  // output cells still folded
  // 2D, once cells were subdivided: the reference corners (in its mesh cell) of every row.
  std::vector<std::array<Point<2>, 4>> row_corners;
  if constexpr (dim == 3) {
    for (Index c = 0; c < ncells; ++c)
      if (folded_cell[static_cast<std::size_t>(c)]) folded.push_back(c);
  } else {
    // Cells that do not fold keep their rows (in order); the pieces of the
    // others follow them.
    const auto row = [&](Index i) {
      std::vector<Index> nodes(static_cast<std::size_t>(nloc));
      for (int k = 0; k < nloc; ++k) nodes[static_cast<std::size_t>(k)] = out.cells(i, k);
      return nodes;
    };
    std::vector<Index> unfolded_rows;
    std::vector<std::vector<Index>> kept;
    std::vector<Index> kept_ids, kept_sources;
    std::vector<std::array<Point<2>, 4>> kept_corners;
    std::vector<Region> pending;
    std::vector<std::vector<Index>> pending_nodes;
    std::array<Point<2>, 4> reference_vertices{};
    for (int v = 0; v < nvert; ++v)
      reference_vertices[static_cast<std::size_t>(v)] = linear.nodes().row(v).transpose();
    for (Index i = 0; i < ncells; ++i)
      if (folded_cell[static_cast<std::size_t>(i)]) {
        pending.push_back({i, reference_vertices});
        pending_nodes.push_back(row(i));
      }
    if (!pending.empty())
      for (Index i = 0; i < ncells; ++i)
        if (!folded_cell[static_cast<std::size_t>(i)]) unfolded_rows.push_back(i);
    std::unordered_map<XiKey, Index, XiKeyHash> by_xi;
    std::vector<char> subdivided(cells.size(), 0);
    const auto node_xi = [&](const Region& region, int k) {
      Point<2> xi = Point<2>::Zero();
      for (int v = 0; v < nvert; ++v) xi += geometry(k, v) * region.xi[static_cast<std::size_t>(v)];
      return xi;
    };
    // Nodes of the regions being split are reused by the children they touch.
    const auto remember_pending = [&] {
      for (std::size_t r = 0; r < pending.size(); ++r) {
        subdivided[static_cast<std::size_t>(pending[r].cell_index)] = 1;
        for (int k = 0; k < nloc; ++k)
          by_xi.try_emplace(xi_key(pending[r].cell_index, node_xi(pending[r], k)),
                            pending_nodes[r][static_cast<std::size_t>(k)]);
      }
    };
    // New nodes (mesh cell, reference point): Ω0 positions by the mesh cell's
    // straight geometry, Ω1 positions and det J_f by f.
    struct Placed {
      Points<2> x0, x1;
      VectorX det;
    };
    const auto place = [&](const std::vector<std::pair<Index, Point<2>>>& sources) {
      const Index added = static_cast<Index>(sources.size());
      Points<2> xi(added, 2);
      for (Index j = 0; j < added; ++j) xi.row(j) = sources[static_cast<std::size_t>(j)].second.transpose();
      Placed placed;
      placed.x0 = omega0_points(mesh, xi, [&](Index j) {
        return cells[static_cast<std::size_t>(sources[static_cast<std::size_t>(j)].first)];
      });
      placed.x1 = warp_nodes(map, placed.x0, &placed.det);
      return placed;
    };
    const auto append = [&](const std::vector<std::pair<Index, Point<2>>>& sources, const Placed& placed) {
      const Index old_count = out.points.rows(), added = placed.x0.rows();
      out.reference_points.conservativeResize(old_count + added, 2);
      out.points.conservativeResize(old_count + added, 2);
      out.map_det.conservativeResize(old_count + added);
      out.reference_points.bottomRows(added) = placed.x0;
      out.points.bottomRows(added) = placed.x1;
      out.map_det.tail(added) = placed.det;
      for (const auto& source : sources)
        out.added_node_source_.push_back({cells[static_cast<std::size_t>(source.first)], source.second});
    };
    const auto keep = [&](const Region& region, std::vector<Index> nodes) {
      kept.push_back(std::move(nodes));
      kept_ids.push_back(cells[static_cast<std::size_t>(region.cell_index)]);
      kept_sources.push_back(region.cell_index);
      kept_corners.push_back(region.xi);
    };
    constexpr int max_depth = 4;
    for (int depth = 1; depth <= max_depth && !pending.empty(); ++depth) {
      remember_pending();
      std::vector<Region> next;
      std::vector<std::vector<Index>> next_nodes;
      std::vector<std::pair<Index, Point<2>>> new_sources;
      for (std::size_t r = 0; r < pending.size(); ++r)
        for (const Region& child : split(pending[r], mesh.cell_type)) {
          std::vector<Index> nodes(static_cast<std::size_t>(nloc));
          for (int k = 0; k < nloc; ++k) {
            const Point<2> xi = node_xi(child, k);
            const auto [it, inserted] = by_xi.try_emplace(
                xi_key(child.cell_index, xi), out.points.rows() + static_cast<Index>(new_sources.size()));
            if (inserted) new_sources.emplace_back(child.cell_index, xi);
            nodes[static_cast<std::size_t>(k)] = it->second;
          }
          next.push_back(child);
          next_nodes.push_back(std::move(nodes));
        }
      append(new_sources, place(new_sources));
      pending.clear();
      pending_nodes.clear();
      for (std::size_t r = 0; r < next.size(); ++r) {
        if (tangled(next_nodes[r])) {
          pending.push_back(next[r]);
          pending_nodes.push_back(std::move(next_nodes[r]));
        } else {
          keep(next[r], std::move(next_nodes[r]));
        }
      }
    }
    for (std::size_t r = 0; r < pending.size(); ++r) {
      folded.push_back(static_cast<Index>(unfolded_rows.size() + kept.size()));
      keep(pending[r], std::move(pending_nodes[r]));
    }
    out.num_subdivided_cells = static_cast<Index>(std::count(subdivided.begin(), subdivided.end(), 1));
    if (out.num_subdivided_cells > 0) {
      const Index nkept = static_cast<Index>(unfolded_rows.size() + kept.size());
      IndexTable table(nkept, nloc);
      std::vector<Index> ids, sources;
      ids.reserve(static_cast<std::size_t>(nkept));
      sources.reserve(static_cast<std::size_t>(nkept));
      for (std::size_t r = 0; r < unfolded_rows.size(); ++r) {
        table.row(static_cast<Index>(r)) = out.cells.row(unfolded_rows[r]);
        ids.push_back(cells[static_cast<std::size_t>(unfolded_rows[r])]);
        sources.push_back(unfolded_rows[r]);
      }
      for (std::size_t r = 0; r < kept.size(); ++r) {
        for (int k = 0; k < nloc; ++k)
          table(static_cast<Index>(unfolded_rows.size() + r), k) =
              static_cast<TableIndex>(kept[r][static_cast<std::size_t>(k)]);
        ids.push_back(kept_ids[r]);
        sources.push_back(kept_sources[r]);
      }
      out.cells = std::move(table);
      out.cell_ids = std::move(ids);
      out.source_cells = std::move(sources);
      row_corners.assign(unfolded_rows.size(), reference_vertices);
      row_corners.insert(row_corners.end(), kept_corners.begin(), kept_corners.end());
    }
  }
  // Quadrilaterals that fold even straight become triangles first; the
  // remaining cells are then straightened without moving the triangles' nodes.
  std::vector<char> fixed = frozen;
  if constexpr (dim == 2)
    if (mesh.cell_type == CellType::quadrilateral && nloc == 9 && !folded.empty()) {
      std::vector<std::pair<Index, Point<2>>> added;  // (local cell, reference point)
      write_folded_quadrilaterals_as_triangles(out, mesh, map, tangled, frozen, row_corners, folded, added);
      for (const auto& [local, xi] : added)
        out.added_node_source_.push_back({cells[static_cast<std::size_t>(local)], xi});
      if (out.num_split_cells > 0) {
        fixed.resize(static_cast<std::size_t>(out.points.rows()), 0);
        for (Index r = 0; r < out.simplex_cells.rows(); ++r)
          for (Index k = 0; k < out.simplex_cells.cols(); ++k)
            fixed[static_cast<std::size_t>(out.simplex_cells(r, k))] = 1;
      }
    }
  const std::vector<Index> still =
      straighten_folded_cells(out, geometry, nvert, tangled, std::move(folded), fixed);
  if constexpr (dim == 2)
    if (mesh.cell_type == CellType::quadrilateral && nloc == 9 && !still.empty()) {
      // Quadrilaterals the pulls did not untangle (or folded): cut as above,
      // now without moving any node of the cells written so far.
      std::vector<Index> rows = still;
      std::vector<std::pair<Index, Point<2>>> added;
      write_folded_quadrilaterals_as_triangles(out, mesh, map, tangled, fixed, row_corners, rows, added);
      for (const auto& [local, xi] : added)
        out.added_node_source_.push_back({cells[static_cast<std::size_t>(local)], xi});
      out.num_tangled_cells = static_cast<Index>(rows.size());  // the quadrilaterals still folded
    }
  // Triangles and tetrahedra that still fold: straight pieces placed by f.
  const bool simplex = mesh.cell_type == CellType::triangle || mesh.cell_type == CellType::tetrahedron;
  if (simplex && nloc == (dim == 2 ? 6 : 10) && !still.empty()) {
    const auto corner = [&](Index row, int v) -> Point<dim> {
      if constexpr (dim == 2)
        if (!row_corners.empty())
          return row_corners[static_cast<std::size_t>(row)][static_cast<std::size_t>(v)];
      return linear.nodes().row(v).transpose();
    };
    std::vector<std::pair<Index, Point<dim>>> added;  // (local cell, reference point)
    const Index cut = cut_folded_simplices(out, mesh, map, corner, still, added);
    for (const auto& [local, xi] : added)
      out.added_node_source_.push_back({cells[static_cast<std::size_t>(local)], xi});
    out.num_split_cells += cut;
    out.num_tangled_cells -= cut;
  }
  if constexpr (dim == 3)
    if (mesh.cell_type == CellType::hexahedron && nloc == 27 && !still.empty()) {
      std::vector<std::pair<Index, Point<3>>> added;  // (local cell, reference point)
      out.num_tangled_cells = write_folded_hexahedra_as_tetrahedra(out, mesh, map, still, added);
      for (const auto& [local, xi] : added)
        out.added_node_source_.push_back({cells[static_cast<std::size_t>(local)], xi});
    }
  if constexpr (dim == 2) out.num_tangled_cells += folded_triangles(out);
  log::debug("output mesh: fold check in ", format_seconds(watch.seconds()), " (CPU ",
             format_seconds(process_cpu_seconds() - cpu), ")");
  return out;
}

template <int dim>
void log_untangling(MPI_Comm comm, const OutputMesh<dim>& out) {
  long long counts[5] = {out.num_mesh_cells, out.num_subdivided_cells, out.num_straightened_cells,
                         out.num_split_cells, out.num_tangled_cells};
  MPI_Allreduce(MPI_IN_PLACE, counts, 5, MPI_LONG_LONG, MPI_SUM, comm);
  if (counts[1] > 0)
    log::info("output: ", counts[1], " of ", counts[0],
              " cells subdivided to keep them untangled (their curved geometry folded)");
  if (counts[2] > 0)
    log::info("output: ", counts[2],
              " written cells drawn less curved (nodes pulled toward the straight cell) where f is not "
              "smooth enough for curved cells to follow it; the solution is unaffected");
  if (counts[3] > 0)
    log::info("output: ", counts[3],
              " cells written as straight triangles or tetrahedra (even their straight cell folded: f "
              "opens a corner or turns sharply there); the solution is unaffected");
  long long left_out = out.num_left_out_pieces;
  double left_out_volume = out.left_out_volume;
  MPI_Allreduce(MPI_IN_PLACE, &left_out, 1, MPI_LONG_LONG, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &left_out_volume, 1, MPI_DOUBLE, MPI_SUM, comm);
  if (left_out > 0)
    log::info("output: ", left_out, " straight pieces smaller than 1e-6 of their cell left out, together ",
              left_out_volume,
              " of a cell's volume (next to a point where f is not differentiable some pieces fold at "
              "every scale); the solution is unaffected");
  if (counts[4] > 0)
    log::warning("output: ", counts[4],
                 " written cells still fold and are drawn folded; the solution is unaffected (f is "
                 "strongly anisotropic there; a finer mesh or another map helps)");
}

template <int dim>
std::vector<double> OutputMesh<dim>::cell_values(const VectorX& per_local_cell) const {
  std::vector<double> values(source_cells.size());
  for (std::size_t i = 0; i < source_cells.size(); ++i) values[i] = per_local_cell(source_cells[i]);
  return values;
}

template <int dim>
std::vector<double> OutputMesh<dim>::interpolate(const DofMap<dim>& dofs, const DofDistribution<dim>& dist,
                                                 const VectorX& relevant_values) const {
  const Index nmesh = static_cast<Index>(node_in_cell_.size());
  std::vector<double> values;
  resize_prefaulted(values, node_in_cell_.size() + added_node_source_.size());
  const Index ndofs = dofs.cell_dofs().cols();
  const auto value = [&](const auto& phi, Index row, Index cell) {
    double v = 0;
    for (Index j = 0; j < ndofs; ++j)
      v += phi(row, j) * relevant_values(dist.relevant_index(dofs.cell_dofs()(cell, j)));
    return v;
  };
  // Nodes of the mesh cells: the basis at the output element's nodes, once.
  const LagrangeElement<dim> output_element(cell_type, order);
  const Index nloc = output_element.num_dofs();
  const MatrixX phi_nodes = dofs.element().values(output_element.nodes());  // nodes x element dofs
  parallel_for(nmesh, 1 << 14, [&](Index first, Index last) {
    for (Index p = first; p < last; ++p) {
      const Index code = node_in_cell_[static_cast<std::size_t>(p)];
      values[static_cast<std::size_t>(p)] = value(phi_nodes, code % nloc, code / nloc);
    }
  });
  // Nodes added by subdivision: the basis at their points, in blocks.
  constexpr Index block = 4096;
  const Index nadded = static_cast<Index>(added_node_source_.size());
  for (Index start = 0; start < nadded; start += block) {
    const Index count = std::min(block, nadded - start);
    Points<dim> xi(count, dim);
    for (Index p = 0; p < count; ++p)
      xi.row(p) = added_node_source_[static_cast<std::size_t>(start + p)].xi.transpose();
    const MatrixX phi = dofs.element().values(xi);  // nodes x element dofs
    for (Index p = 0; p < count; ++p)
      values[static_cast<std::size_t>(nmesh + start + p)] =
          value(phi, p, added_node_source_[static_cast<std::size_t>(start + p)].cell);
  }
  return values;
}

template struct OutputMesh<2>;
template struct OutputMesh<3>;
template OutputMesh<2> make_output_mesh(const Mesh<2>&, const DofDistribution<2>&, const mapping::Map<2>&,
                                        int);
template OutputMesh<3> make_output_mesh(const Mesh<3>&, const DofDistribution<3>&, const mapping::Map<3>&,
                                        int);
template void log_untangling(MPI_Comm, const OutputMesh<2>&);
template void log_untangling(MPI_Comm, const OutputMesh<3>&);

}  // namespace warpfem::fem
