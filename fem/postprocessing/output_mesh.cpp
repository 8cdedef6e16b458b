#include "fem/postprocessing/output_mesh.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cstring>
#include <functional>
#include <numeric>
#include <string>
#include <unordered_map>

#include "core/error.hpp"
#include "core/log.hpp"
#include "fem/geometry/warped_geometry.hpp"
#include "fem/reference/lagrange_element.hpp"

namespace warpfem::fem {

namespace {

// Where the geometric Jacobian of an output cell is checked: its nodes and a
// lattice of step 1/8 on the reference cell (which contains the 5×5 lattice a
// viewer samples).
template <int dim>
Points<dim> jacobian_check_points(const LagrangeElement<dim>& element) {
  constexpr int steps = 8;
  std::vector<Point<dim>> pts;
  for (Index k = 0; k < element.nodes().rows(); ++k) pts.push_back(element.nodes().row(k).transpose());
  const bool simplex =
      element.cell_type() == CellType::triangle || element.cell_type() == CellType::tetrahedron;
  if constexpr (dim == 2) {
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; j <= (simplex ? steps - i : steps); ++j)
        pts.push_back(Point<2>(static_cast<double>(i) / steps, static_cast<double>(j) / steps));
  } else {
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; j <= (simplex ? steps - i : steps); ++j)
        for (int k = 0; k <= (simplex ? steps - i - j : steps); ++k)
          pts.push_back(Point<3>(static_cast<double>(i) / steps, static_cast<double>(j) / steps,
                                 static_cast<double>(k) / steps));
  }
  Points<dim> out(static_cast<Index>(pts.size()), dim);
  for (std::size_t p = 0; p < pts.size(); ++p) out.row(static_cast<Index>(p)) = pts[p].transpose();
  return out;
}

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

// Cells whose curved geometry still folds — at a vertex where f is not
// differentiable the quadratic interpolant of f folds at any subdivision
// depth — get their non-vertex nodes pulled toward the straight cell spanned by
// their mapped vertices: x = c + t (f(x0) − c), with c the node's place on that
// straight cell and t halved, down to 0, until no cell holding a pulled node
// folds. Shared nodes move for every cell that holds them, so no crack opens;
// `frozen` nodes (on edges and faces another rank's cells share, whose copies
// there would not move) stay put. The field values stay those at x0.
template <int dim, class Tangled>
void straighten_folded_cells(OutputMesh<dim>& out, const MatrixX& geometry, int nvert, const Tangled& tangled,
                             std::vector<Index> folded, const std::vector<char>& frozen) {
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
  if (work.empty()) return;
  // The cells of every node (compressed rows).
  std::vector<Index> start(static_cast<std::size_t>(npoints) + 1, 0);
  for (Index c = 0; c < ncells; ++c)
    for (Index k = 0; k < nloc; ++k) ++start[static_cast<std::size_t>(out.cells(c, k)) + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<Index> holders(static_cast<std::size_t>(start.back()));
  {
    std::vector<Index> fill(start.begin(), start.end() - 1);
    for (Index c = 0; c < ncells; ++c)
      for (Index k = 0; k < nloc; ++k)
        holders[static_cast<std::size_t>(fill[static_cast<std::size_t>(out.cells(c, k))]++)] = c;
  }
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
    std::fill(seen.begin(), seen.end(), 0);
    for (const Index node : moved)
      for (Index j = start[static_cast<std::size_t>(node)]; j < start[static_cast<std::size_t>(node) + 1];
           ++j) {
        const Index c = holders[static_cast<std::size_t>(j)];
        if (!seen[static_cast<std::size_t>(c)]) {
          seen[static_cast<std::size_t>(c)] = 1;
          if (tangled(row(c))) next.push_back(c);
        }
      }
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
  out.num_tangled_cells = 0;
  for (Index c = 0; c < ncells; ++c) {
    const bool keep = !undone(c);
    out.num_straightened_cells += keep && straightened[static_cast<std::size_t>(c)] ? 1 : 0;
    out.num_tangled_cells += (keep ? folded_after : folded_before)[static_cast<std::size_t>(c)];
  }
}

}  // namespace

template <int dim>
OutputMesh<dim> make_output_mesh(const Mesh<dim>& mesh, const DofDistribution<dim>& dist,
                                 const mapping::Map<dim>& map, int order) {
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
  out.cells.resize(static_cast<Index>(cells.size()), nloc);
  out.cell_ids = cells;
  out.source_cells.resize(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) out.source_cells[i] = static_cast<Index>(i);
  // Nodes the local cells share: vertices by their number, edge nodes by their
  // edge's two vertex numbers, face nodes (Q2 hexahedra) by their face's sorted
  // vertex numbers (no mesh-wide numbering of edges or faces, so the output of
  // a level stored only around this rank's cells works too); interior nodes
  // belong to one cell.
  using Key = std::array<Index, dim == 2 ? 2 : 4>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = std::hash<Index>()(k[0]);
      for (std::size_t i = 1; i < k.size(); ++i)
        h ^= std::hash<Index>()(k[i]) * (i == 1 ? 0x9E3779B97F4A7C15ULL : 0xC2B2AE3D27D4EB4FULL * i);
      return h;
    }
  };
  // Vertices of other ranks' cells: edge and face nodes among them are never
  // pulled (straighten_folded_cells), since each rank decides its pulls alone.
  std::vector<char> foreign(static_cast<std::size_t>(mesh.num_vertices()), 0);
  {
    std::vector<char> local(static_cast<std::size_t>(mesh.num_cells()), 0);
    for (const Index c : cells) local[static_cast<std::size_t>(c)] = 1;
    // A partial level stores only the cells of its present ranges.
    const std::vector<std::array<Index, 2>> stored =
        mesh.partial ? mesh.present_cells : std::vector<std::array<Index, 2>>{{0, mesh.num_cells()}};
    for (const auto& [first, last] : stored)
      for (Index c = first; c < last; ++c)
        if (!local[static_cast<std::size_t>(c)])
          for (int v = 0; v < nvert; ++v) foreign[static_cast<std::size_t>(mesh.cells(c, v))] = 1;
  }
  std::vector<char> frozen;  // per node
  std::unordered_map<Key, Index, KeyHash> index;
  index.reserve(cells.size() * static_cast<std::size_t>(nloc) / 2 + 1);
  std::vector<Point<dim>> positions;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Index c = cells[i];
    for (int k = 0; k < nloc; ++k) {
      Index node = -1;
      if (k < face_nodes_end) {
        Key key;
        key.fill(-1);
        if (k < nvert) {
          key[0] = mesh.cells(c, k);
        } else if (k < edge_nodes_end) {
          const auto& e = edges[static_cast<std::size_t>(k - nvert)];
          const Index p = mesh.cells(c, e[0]), q = mesh.cells(c, e[1]);
          key[0] = std::min(p, q);
          key[1] = std::max(p, q);
        } else if constexpr (dim == 3) {
          const auto& f = cell_faces(mesh.cell_type)[static_cast<std::size_t>(k - edge_nodes_end)];
          for (std::size_t j = 0; j < f.size(); ++j) key[j] = mesh.cells(c, f[j]);
          for (std::size_t a = 1; a < f.size(); ++a)  // sorted: insertion into at most four
            for (std::size_t b = a; b > 0 && key[b - 1] > key[b]; --b) std::swap(key[b - 1], key[b]);
        }
        const auto [it, inserted] = index.try_emplace(key, static_cast<Index>(positions.size()));
        node = it->second;
        if (!inserted) {
          out.cells(static_cast<Index>(i), k) = node;
          continue;
        }
      }
      if (node < 0) node = static_cast<Index>(positions.size());
      Point<dim> x = Point<dim>::Zero();
      for (int v = 0; v < nvert; ++v) x += geometry(k, v) * mesh.vertex(mesh.cells(c, v));
      positions.push_back(x);
      bool shared = k >= nvert && k < face_nodes_end;
      if (shared) {
        Key key;  // the vertices of the edge or face the node lies on
        key.fill(-1);
        if (k < edge_nodes_end) {
          const auto& e = edges[static_cast<std::size_t>(k - nvert)];
          key[0] = mesh.cells(c, e[0]);
          key[1] = mesh.cells(c, e[1]);
        } else if constexpr (dim == 3) {
          const auto& f = cell_faces(mesh.cell_type)[static_cast<std::size_t>(k - edge_nodes_end)];
          for (std::size_t j = 0; j < f.size(); ++j) key[j] = mesh.cells(c, f[j]);
        }
        for (const Index v : key) shared = shared && (v < 0 || foreign[static_cast<std::size_t>(v)]);
      }
      frozen.push_back(shared ? 1 : 0);
      out.node_source_.push_back({c, element.nodes().row(k).transpose()});
      out.cells(static_cast<Index>(i), k) = node;
    }
  }
  const Index n = static_cast<Index>(positions.size());
  out.reference_points.resize(n, dim);
  for (Index i = 0; i < n; ++i)
    out.reference_points.row(i) = positions[static_cast<std::size_t>(i)].transpose();
  out.points = warp_nodes(map, out.reference_points, &out.map_det);
  out.num_mesh_cells = static_cast<Index>(cells.size());

  // The quadratic interpolant of f can fold a cell even where det J_f > 0 (a
  // strongly curved cell near a reentrant vertex of Ω1): in 2D such cells are
  // replaced by four children whose nodes are again placed by f, recursively.
  const Points<dim> check = jacobian_check_points(element);
  const auto check_gradients = element.gradients(check);
  // True if the cell whose k-th node lies at node_position(k) folds somewhere.
  const auto folds = [&](const auto& node_position) {
    for (Index p = 0; p < check.rows(); ++p) {
      Eigen::Matrix<double, dim, dim> J = Eigen::Matrix<double, dim, dim>::Zero();
      for (int k = 0; k < nloc; ++k) {
        const Point<dim> x = node_position(k);
        for (int d = 0; d < dim; ++d) J.col(d) += check_gradients[static_cast<std::size_t>(d)](p, k) * x;
      }
      if constexpr (dim == 2) {
        if (!(J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0) > 0)) return true;
      } else {
        if (!(J.determinant() > 0)) return true;
      }
    }
    return false;
  };
  const auto tangled = [&](const std::vector<Index>& nodes) {
    return folds(
        [&](int k) -> Point<dim> { return out.points.row(nodes[static_cast<std::size_t>(k)]).transpose(); });
  };
  std::vector<Index> folded;  // output cells still folded
  if constexpr (dim == 3) {
    for (Index c = 0; c < out.cells.rows(); ++c) {
      std::vector<Index> nodes(static_cast<std::size_t>(nloc));
      for (int k = 0; k < nloc; ++k) nodes[static_cast<std::size_t>(k)] = out.cells(c, k);
      if (tangled(nodes)) folded.push_back(c);
    }
  } else {
    std::vector<std::vector<Index>> kept;
    std::vector<Index> kept_ids, kept_sources;
    std::vector<Region> pending;
    std::vector<std::vector<Index>> pending_nodes;
    std::array<Point<2>, 4> reference_vertices{};
    for (int v = 0; v < nvert; ++v)
      reference_vertices[static_cast<std::size_t>(v)] = linear.nodes().row(v).transpose();
    for (Index i = 0; i < out.cells.rows(); ++i) {
      std::vector<Index> nodes(static_cast<std::size_t>(nloc));
      for (int k = 0; k < nloc; ++k) nodes[static_cast<std::size_t>(k)] = out.cells(i, k);
      if (tangled(nodes)) {
        pending.push_back({i, reference_vertices});
        pending_nodes.push_back(std::move(nodes));
      } else {
        kept.push_back(std::move(nodes));
        kept_ids.push_back(cells[static_cast<std::size_t>(i)]);
        kept_sources.push_back(i);
      }
    }
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
      const MatrixX weights = linear.values(xi);
      Placed placed;
      placed.x0.resize(added, 2);
      for (Index j = 0; j < added; ++j) {
        const Index c = cells[static_cast<std::size_t>(sources[static_cast<std::size_t>(j)].first)];
        Point<2> x = Point<2>::Zero();
        for (int v = 0; v < nvert; ++v) x += weights(j, v) * mesh.vertex(mesh.cells(c, v));
        placed.x0.row(j) = x.transpose();
      }
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
        out.node_source_.push_back({cells[static_cast<std::size_t>(source.first)], source.second});
    };
    const auto keep = [&](const Region& region, std::vector<Index> nodes) {
      kept.push_back(std::move(nodes));
      kept_ids.push_back(cells[static_cast<std::size_t>(region.cell_index)]);
      kept_sources.push_back(region.cell_index);
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
      folded.push_back(static_cast<Index>(kept.size()));
      keep(pending[r], std::move(pending_nodes[r]));
    }
    out.num_subdivided_cells = static_cast<Index>(std::count(subdivided.begin(), subdivided.end(), 1));
    if (out.num_subdivided_cells > 0) {
      out.cells.resize(static_cast<Index>(kept.size()), nloc);
      for (std::size_t r = 0; r < kept.size(); ++r)
        for (int k = 0; k < nloc; ++k)
          out.cells(static_cast<Index>(r), k) = kept[r][static_cast<std::size_t>(k)];
      out.cell_ids = std::move(kept_ids);
      out.source_cells = std::move(kept_sources);
    }
  }
  straighten_folded_cells(out, geometry, nvert, tangled, std::move(folded), frozen);
  return out;
}

template <int dim>
void log_untangling(MPI_Comm comm, const OutputMesh<dim>& out) {
  long long counts[4] = {out.num_mesh_cells, out.num_subdivided_cells, out.num_straightened_cells,
                         out.num_tangled_cells};
  MPI_Allreduce(MPI_IN_PLACE, counts, 4, MPI_LONG_LONG, MPI_SUM, comm);
  if (counts[1] > 0)
    log::info("output: ", counts[1], " of ", counts[0],
              " cells subdivided to keep them untangled (their curved geometry folded)");
  if (counts[2] > 0)
    log::info("output: ", counts[2],
              " written cells drawn less curved (nodes pulled toward the straight cell) where f is not "
              "smooth enough for curved cells to follow it; the solution is unaffected");
  if (counts[3] > 0)
    log::warning("output: ", counts[3],
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
VectorX OutputMesh<dim>::interpolate(const DofMap<dim>& dofs, const DofDistribution<dim>& dist,
                                     const VectorX& relevant_values) const {
  VectorX values(static_cast<Index>(node_source_.size()));
  // In blocks, so the matrix of basis values stays small on large meshes.
  constexpr Index block = 4096;
  for (Index start = 0; start < values.size(); start += block) {
    const Index count = std::min(block, values.size() - start);
    Points<dim> xi(count, dim);
    for (Index p = 0; p < count; ++p)
      xi.row(p) = node_source_[static_cast<std::size_t>(start + p)].xi.transpose();
    const MatrixX phi = dofs.element().values(xi);  // nodes x element dofs
    for (Index p = 0; p < count; ++p) {
      const Index c = node_source_[static_cast<std::size_t>(start + p)].cell;
      double v = 0;
      for (Index j = 0; j < phi.cols(); ++j)
        v += phi(p, j) * relevant_values(dist.relevant_index(dofs.cell_dofs()(c, j)));
      values(start + p) = v;
    }
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
