#include "fem/hierarchy/refine_by_position.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/prefault.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"

namespace warpfem::fem {

namespace {

constexpr TableIndex kUnknown = -1;

/// Integer coordinates of a point in its base cell on the 2^k lattice:
/// barycentric (simplices) or tensor-product (the unused entries 0).
using Coords = std::array<std::int32_t, 4>;
/// The point's weight at each local vertex of the cell (or facet): its
/// barycentric coordinates, or the products of its tensor coordinates.
using Weights = std::array<std::int64_t, 8>;

std::size_t at(int i) {
  return static_cast<std::size_t>(i);
}

/// A cell or facet shape: its refinement table and where its vertices and
/// refinement nodes sit, in integer coordinates.
struct Shape {
  bool simplex = true;
  int dim = 0;  ///< tensor shapes: the number of coordinates
  RefinementTable table;
  std::array<Coords, 8> corner{};  ///< local vertex j at lattice scale 1
  /// Local node l of the table is the average of these local vertices (in the
  /// order refine_uniformly sums them for its position).
  std::vector<std::vector<int>> node_corners;

  int vertices() const { return table.vertices; }

  Weights weights(const Coords& y, std::int64_t scale) const {
    Weights w{};
    for (int v = 0; v < vertices(); ++v) {
      if (simplex) {
        w[at(v)] = y[at(v)];
        continue;
      }
      std::int64_t p = 1;
      for (int d = 0; d < dim; ++d) p *= corner[at(v)][at(d)] != 0 ? y[at(d)] : scale - y[at(d)];
      w[at(v)] = p;
    }
    return w;
  }
  /// The coordinates of the point with weights `w` (the inverse of weights()).
  Coords coordinates(const Weights& w, std::int64_t scale) const {
    Coords y{};
    if (simplex) {
      for (int v = 0; v < vertices(); ++v) y[at(v)] = static_cast<std::int32_t>(w[at(v)]);
      return y;
    }
    std::int64_t lower = 1;  // scale^(dim - 1): the weights of one coordinate's slab sum to y_d times it
    for (int d = 1; d < dim; ++d) lower *= scale;
    for (int d = 0; d < dim; ++d) {
      std::int64_t s = 0;
      for (int v = 0; v < vertices(); ++v)
        if (corner[at(v)][at(d)] != 0) s += w[at(v)];
      y[at(d)] = static_cast<std::int32_t>(s / lower);
    }
    return y;
  }
  /// The local vertices with a non-zero weight: the sub-entity holding the point.
  int support(const Coords& y, std::int64_t scale) const {
    const Weights w = weights(y, scale);
    int mask = 0;
    for (int v = 0; v < vertices(); ++v) mask |= w[at(v)] != 0 ? 1 << v : 0;
    return mask;
  }
  int full_mask() const { return (1 << vertices()) - 1; }
  /// Local node `l` of a cell with vertices at `x`, at twice their scale.
  Coords node(const std::array<Coords, 8>& x, int l) const {
    const std::vector<int>& c = node_corners[at(l)];
    const auto n = static_cast<std::int32_t>(c.size());
    Coords out{};
    for (int d = 0; d < 4; ++d) {
      std::int32_t s = 0;
      for (int j : c) s += x[at(j)][at(d)];
      out[at(d)] = 2 * s / n;  // exact: the nodes lie on the finer lattice
    }
    return out;
  }
};

Shape shape_of(CellType type) {
  Shape s;
  s.table = refinement_table(type);
  s.simplex = type == CellType::triangle || type == CellType::tetrahedron;
  s.dim = cell_dimension(type);
  // Tensor corners in the layout of reference_cell.hpp (counter-clockwise
  // bottom, then top).
  constexpr std::array<Coords, 8> kTensor{{{0, 0, 0, 0},
                                           {1, 0, 0, 0},
                                           {1, 1, 0, 0},
                                           {0, 1, 0, 0},
                                           {0, 0, 1, 0},
                                           {1, 0, 1, 0},
                                           {1, 1, 1, 0},
                                           {0, 1, 1, 0}}};
  for (int v = 0; v < s.vertices(); ++v)
    for (int d = 0; d < 4; ++d) s.corner[at(v)][at(d)] = s.simplex ? (d == v ? 1 : 0) : kTensor[at(v)][at(d)];
  const RefinementTable& t = s.table;
  for (int v = 0; v < t.vertices; ++v) s.node_corners.push_back({v});
  for (const auto& e : cell_edges(type)) s.node_corners.push_back({e[0], e[1]});
  for (int f = 0; f < t.faces; ++f) s.node_corners.push_back(cell_faces(type)[at(f)]);
  if (t.centres) {
    std::vector<int> all(static_cast<std::size_t>(t.vertices));
    for (int v = 0; v < t.vertices; ++v) all[at(v)] = v;
    s.node_corners.push_back(all);
  }
  require(static_cast<int>(s.node_corners.size()) == t.nodes(), "refine_partially: inconsistent node table");
  return s;
}

/// A boundary edge of a quadrilateral mesh: halves (a, m) and (m, b).
Shape segment_shape() {
  Shape s;
  s.simplex = false;
  s.dim = 1;
  s.table.vertices = 2;
  s.table.centres = 1;
  s.table.children = 2;
  s.table.child_nodes[0][0] = 0, s.table.child_nodes[0][1] = 2;
  s.table.child_nodes[1][0] = 2, s.table.child_nodes[1][1] = 1;
  s.corner[1][0] = 1;
  s.node_corners = {{0}, {1}, {0, 1}};
  return s;
}

/// The sub-entities of a cell shape as vertex masks: vertices, edges, faces
/// (3D), the cell; slot_of_mask numbers them.
struct Entities {
  std::vector<int> mask, dimension;
  std::array<std::int8_t, 256> slot_of_mask{};

  explicit Entities(CellType type) {
    slot_of_mask.fill(-1);
    const int nv = vertices_per_cell(type), dim = cell_dimension(type);
    const auto add = [&](int m, int d) {
      slot_of_mask[at(m)] = static_cast<std::int8_t>(mask.size());
      mask.push_back(m), dimension.push_back(d);
    };
    for (int v = 0; v < nv; ++v) add(1 << v, 0);
    for (const auto& e : cell_edges(type)) add(1 << e[0] | 1 << e[1], 1);
    if (dim == 3)
      for (const auto& f : cell_faces(type)) {
        int m = 0;
        for (int v : f) m |= 1 << v;
        add(m, 2);
      }
    add((1 << nv) - 1, dim);
  }
  int count() const { return static_cast<int>(mask.size()); }
  int slot(int m) const { return slot_of_mask[at(m)]; }
};

/// splitmix64's finalizer: the hash of a 64-bit key.
std::uint64_t mix(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

std::uint64_t key_of(const Coords& y) {
  std::uint64_t key = 0;
  for (int d = 0; d < 4; ++d) key = key << 16 | static_cast<std::uint64_t>(y[at(d)]);
  return key;
}
Coords coords_of(std::uint64_t key) {
  Coords y{};
  for (int d = 3; d >= 0; --d, key >>= 16) y[at(d)] = static_cast<std::int32_t>(key & 0xFFFF);
  return y;
}

/// Node number by key, open addressing with linear probing: one flat array
/// (the node-based std::unordered_map spent most of the refinement chasing
/// and allocating nodes). clear() keeps the capacity.
class FlatNumbering {
 public:
  /// The number stored for `key`, and whether it was absent (then kEmpty, to be set).
  std::pair<TableIndex*, bool> find_or_insert(std::uint64_t key) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    std::size_t i = static_cast<std::size_t>(mix(key)) & (slots_.size() - 1);
    for (;; i = (i + 1) & (slots_.size() - 1)) {
      Slot& s = slots_[i];
      if (s.value == kEmpty) {
        s.key = key;
        ++size_;
        return {&s.value, true};
      }
      if (s.key == key) return {&s.value, false};
    }
  }
  /// f(key, number) for every stored key.
  template <class F>
  void for_each(const F& f) const {
    for (const Slot& s : slots_)
      if (s.value != kEmpty) f(s.key, s.value);
  }
  void clear() {
    if (size_ == 0) return;
    for (Slot& s : slots_) s.value = kEmpty;
    size_ = 0;
  }
  static constexpr TableIndex kEmpty = -2;

 private:
  struct Slot {
    std::uint64_t key = 0;
    TableIndex value = kEmpty;
  };
  void grow() {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(std::max<std::size_t>(64, 2 * old.size()), Slot{});
    size_ = 0;
    for (const Slot& s : old)
      if (s.value != kEmpty) *find_or_insert(s.key).first = s.value;
  }
  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

/// What the refinement needs of the base level: the first cell around every
/// sub-entity of every base cell, the block that numbers a node lying inside
/// that sub-entity, and the cells around every vertex.
struct BaseSupports {
  const Entities& entities;
  std::vector<Index> owner;  // [cell * entities + slot]
  // The cells around vertex v: around[start[v]] … around[start[v + 1] - 1], increasing.
  std::vector<TableIndex> start;
  std::vector<Index> around;

  template <int dim>
  BaseSupports(const Mesh<dim>& base, const Entities& e) : entities(e) {
    const Index nc = base.num_cells(), nv = base.num_vertices();
    const int nvc = static_cast<int>(base.cells.cols());
    start.assign(static_cast<std::size_t>(nv) + 1, 0);
    for (Index c = 0; c < nc; ++c)
      for (int j = 0; j < nvc; ++j) ++start[static_cast<std::size_t>(base.cells(c, j)) + 1];
    for (Index v = 0; v < nv; ++v)
      start[static_cast<std::size_t>(v + 1)] += start[static_cast<std::size_t>(v)];
    around.resize(static_cast<std::size_t>(start.back()));
    std::vector<TableIndex> fill(start.begin(), start.end() - 1);
    for (Index c = 0; c < nc; ++c)  // increasing cells: each vertex's list is sorted
      for (int j = 0; j < nvc; ++j)
        around[static_cast<std::size_t>(fill[static_cast<std::size_t>(base.cells(c, j))]++)] = c;
    const auto contains = [&](Index c, Index v) {
      for (int j = 0; j < nvc; ++j)
        if (base.cells(c, j) == v) return true;
      return false;
    };
    owner.resize(static_cast<std::size_t>(nc * e.count()));
    for (Index c = 0; c < nc; ++c)
      for (int s = 0; s < e.count(); ++s) {
        const int mask = e.mask[at(s)];
        const int lowest = std::countr_zero(static_cast<unsigned>(mask));
        const Index v0 = base.cells(c, lowest);
        Index first = c;
        for (TableIndex i = start[static_cast<std::size_t>(v0)]; i < start[static_cast<std::size_t>(v0 + 1)];
             ++i) {
          const Index d = around[static_cast<std::size_t>(i)];
          bool all = true;
          for (int j = lowest + 1; j < nvc && all; ++j)
            if (mask & (1 << j)) all = contains(d, base.cells(c, j));
          if (all) {
            first = d;
            break;
          }
        }
        owner[static_cast<std::size_t>(c * e.count() + s)] = first;
      }
  }
  /// The block numbering the nodes inside sub-entity `mask` of base cell `cell`.
  Index of(Index cell, int mask) const {
    return owner[static_cast<std::size_t>(cell * entities.count() + entities.slot(mask))];
  }
};

/// A node's key in base cell `to`, from its coordinates `y` in base cell
/// `from`, which shares the node's sub-entity with it.
template <int dim>
std::uint64_t key_in(const Mesh<dim>& base, const Shape& shape, Index from, Index to, const Coords& y,
                     std::int64_t scale) {
  const Weights w = shape.weights(y, scale);
  Weights z{};
  const int nvc = shape.vertices();
  for (int j = 0; j < nvc; ++j)
    if (w[at(j)] != 0)
      for (int i = 0; i < nvc; ++i)
        if (base.cells(to, i) == base.cells(from, j)) z[at(i)] = w[at(j)];
  return key_of(shape.coordinates(z, scale));
}

/// The nodes on its boundary that each refined block numbered, sorted by key
/// (read by the blocks after it).
class BoundaryNodes {
 public:
  explicit BoundaryNodes(Index blocks) : range_(static_cast<std::size_t>(blocks), {0, 0}) {}
  /// Keeps the boundary nodes of `block`, numbered in `numbers` (keys in its coordinates).
  void keep(Index block, const FlatNumbering& numbers, const Shape& shape, std::int64_t scale) {
    const std::size_t begin = nodes_.size();
    numbers.for_each([&](std::uint64_t key, TableIndex number) {
      // Inside the block (every weight non-zero) nobody else looks.
      if (shape.support(coords_of(key), scale) != shape.full_mask()) nodes_.push_back({key, number});
    });
    std::sort(nodes_.begin() + static_cast<std::ptrdiff_t>(begin), nodes_.end());
    range_[static_cast<std::size_t>(block)] = {begin, nodes_.size()};
  }
  /// The number `owner` gave the node with `key`, or kUnknown.
  TableIndex find(Index owner, std::uint64_t key) const {
    const auto [first, last] = range_[static_cast<std::size_t>(owner)];
    const auto begin = nodes_.begin() + static_cast<std::ptrdiff_t>(first),
               end = nodes_.begin() + static_cast<std::ptrdiff_t>(last);
    const auto it = std::lower_bound(begin, end, std::pair<std::uint64_t, TableIndex>{key, kUnknown});
    return it != end && it->first == key ? it->second : kUnknown;
  }

 private:
  std::vector<std::pair<std::uint64_t, TableIndex>> nodes_;
  std::vector<std::array<std::size_t, 2>> range_;
};

/// The coordinates (in the base cell, scale 2^k) of the vertices of the cells
/// of one block on level base + k, walked in cell order: cell i's ancestors
/// are given by the base-`children` digits of i, and only the digits that
/// changed since the last cell are redone.
class CellCoordinates {
 public:
  CellCoordinates(const Shape& shape, int depth)
      : shape_(shape),
        depth_(depth),
        digits_(static_cast<std::size_t>(depth), -1),
        stack_(static_cast<std::size_t>(depth) + 1) {
    stack_[0] = shape.corner;
  }
  /// Cell i of its block (i in [0, children^depth)): its vertices' coordinates.
  const std::array<Coords, 8>& at(Index i) {
    const RefinementTable& t = shape_.table;
    int changed = depth_;
    for (int d = depth_ - 1; d >= 0; --d, i /= t.children) {
      const int q = static_cast<int>(i % t.children);
      if (digits_[static_cast<std::size_t>(d)] != q) changed = d, digits_[static_cast<std::size_t>(d)] = q;
    }
    for (int d = changed; d < depth_; ++d) {
      const auto& parent = stack_[static_cast<std::size_t>(d)];
      auto& child = stack_[static_cast<std::size_t>(d) + 1];
      const int q = digits_[static_cast<std::size_t>(d)];
      for (int j = 0; j < t.vertices; ++j)
        child[static_cast<std::size_t>(j)] =
            shape_.node(parent, t.child_nodes[static_cast<std::size_t>(q)][static_cast<std::size_t>(j)]);
    }
    return stack_[static_cast<std::size_t>(depth_)];
  }

 private:
  const Shape& shape_;
  int depth_;
  std::vector<int> digits_;
  std::vector<std::array<Coords, 8>> stack_;
};

/// How many vertices, edges and faces a block numbers on the next level, from
/// its counts on this one and its cells (the last column): a refined edge
/// gives a midpoint and two halves; a refined face its centre (quadrilaterals),
/// inner edges and four children; a refined cell its centre (tensor cells),
/// inner edges and inner faces.
using Growth = std::array<std::array<Index, 4>, 3>;
Growth growth_of(CellType type) {
  switch (type) {
    case CellType::tetrahedron: return {{{1, 1, 0, 0}, {0, 2, 3, 1}, {0, 0, 4, 8}}};
    case CellType::hexahedron: return {{{1, 1, 1, 1}, {0, 2, 4, 6}, {0, 0, 4, 12}}};
    case CellType::quadrilateral: return {{{1, 1, 0, 1}, {0, 2, 0, 4}, {0, 0, 0, 0}}};
    default: throw Error("refine_partially: no partial refinement of " + to_string(type) + " levels here");
  }
}

}  // namespace

template <int dim>
void refine_by_position(MeshHierarchy<dim>& h, const std::vector<int>& base_owner, int rank, int levels_above,
                        std::vector<NestedBlocks>& blocks) {
  const int base_level = h.num_levels() - 1;
  h.levels.reserve(h.levels.size() + static_cast<std::size_t>(levels_above));  // references stay valid
  h.transfers.reserve(h.transfers.size() + static_cast<std::size_t>(levels_above));
  const Mesh<dim>& base = h.levels.back();
  const CellType type = base.cell_type;
  require(!base.partial && type != CellType::triangle && cell_dimension(type) == dim,
          "refine_partially: the base level must be a whole mesh of tetrahedra, quadrilaterals or hexahedra");
  require(levels_above <= 15, "refine_partially: at most 15 levels above the base level");
  const Index nb = base.num_cells();
  require(static_cast<Index>(base_owner.size()) == nb,
          "refine_partially: owners do not belong to the base level");
  const Shape shape = shape_of(type);
  const Shape facet_shape = dim == 2 ? segment_shape() : shape_of(facet_type(type));
  const RefinementTable& table = shape.table;
  const RefinementTable& facet_table = facet_shape.table;
  const int nvc = table.vertices, nfv = facet_table.vertices;
  const Entities entities(type);
  const Growth growth = growth_of(type);
  // The local nodes in the order a cell's children first use them.
  std::vector<int> first_use;
  {
    std::array<bool, RefinementTable::kMaxNodes> seen{};
    for (int k = 0; k < table.children; ++k)
      for (int j = 0; j < nvc; ++j)
        if (const int n = table.child_nodes[at(k)][at(j)]; !seen[at(n)])
          seen[at(n)] = true, first_use.push_back(n);
  }

  // 1. Who numbers what on the base level, and how much each block numbers.
  const BaseSupports supports(base, entities);
  std::vector<std::array<Index, 3>> numbered_by(static_cast<std::size_t>(nb),
                                                {0, 0, 0});  // vertices, edges, faces
  for (Index b = 0; b < nb; ++b)
    for (int s = 0; s < entities.count(); ++s)
      if (entities.dimension[at(s)] < dim && supports.of(b, entities.mask[at(s)]) == b)
        ++numbered_by[static_cast<std::size_t>(b)][at(entities.dimension[at(s)])];
  // Every base boundary facet: the cell it bounds and its vertices' places there.
  const Index nbf0 = base.num_boundary_facets();
  std::vector<Index> facet_cell(static_cast<std::size_t>(nbf0), -1);
  std::vector<std::array<int, 4>> facet_local(static_cast<std::size_t>(nbf0));
  for (Index f = 0; f < nbf0; ++f) {
    // The face's first cell is the only one it bounds.
    const TableIndex* v = &base.boundary_facets(f, 0);
    for (TableIndex i = supports.start[static_cast<std::size_t>(v[0])];
         i < supports.start[static_cast<std::size_t>(v[0]) + 1] &&
         facet_cell[static_cast<std::size_t>(f)] < 0;
         ++i) {
      const Index c = supports.around[static_cast<std::size_t>(i)];
      std::array<int, 4> local{-1, -1, -1, -1};
      bool all = true;
      for (int i = 0; i < nfv; ++i) {
        for (int j = 0; j < nvc; ++j)
          if (base.cells(c, j) == v[i]) local[at(i)] = j;
        all = all && local[at(i)] >= 0;
      }
      if (all) facet_cell[static_cast<std::size_t>(f)] = c, facet_local[static_cast<std::size_t>(f)] = local;
    }
    require(facet_cell[static_cast<std::size_t>(f)] >= 0,
            "refine_partially: boundary facet " + std::to_string(f) + " is not a face of a cell");
  }

  // 2. The blocks this rank refines (nested_blocks.hpp).
  const RefinedRing ring = refined_ring(base.cells, base_owner, rank);
  const std::vector<char>& near = ring.near;
  const std::vector<char>& refined = ring.refined;
  const std::vector<Index>& refined_blocks = ring.refined_blocks;
  const std::vector<std::array<Index, 2>>& refined_runs = ring.refined_runs;
  const auto in = [](const std::vector<char>& mask, Index b) {
    return b >= 0 && mask[static_cast<std::size_t>(b)];
  };
  const auto first_of = [](const std::vector<TableIndex>& first, Index b) {
    return first[static_cast<std::size_t>(b)];
  };

  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<TableIndex> coarse_first_vertex;  // empty on the base level (all its vertices are known)
  Index per_block = 1, facets_per_base = 1;
  for (int k = 0; k < levels_above; ++k) {
    const Mesh<dim>& coarse = h.levels.back();
    const Index nv = coarse.num_vertices(), nc = coarse.num_cells();
    const std::int64_t scale = std::int64_t{2} << k;  // of the nodes: twice the coarse cells' lattice
    const std::string where = "refine_partially: level " + std::to_string(base_level + k + 1);
    std::vector<std::array<Index, 3>> fine_numbered(static_cast<std::size_t>(nb));
    std::vector<Index> fine_vertices(static_cast<std::size_t>(nb));
    Index vertices_total = 0;
    for (std::size_t b = 0; b < static_cast<std::size_t>(nb); ++b) {
      for (std::size_t i = 0; i < 3; ++i)
        fine_numbered[b][i] = growth[i][0] * numbered_by[b][0] + growth[i][1] * numbered_by[b][1] +
                              growth[i][2] * numbered_by[b][2] + growth[i][3] * per_block;
      fine_vertices[b] = fine_numbered[b][0];
      vertices_total += fine_vertices[b] - numbered_by[b][0];
    }
    std::vector<TableIndex> first_vertex = block_offsets(fine_vertices, where + " vertices");
    const Index fine_nv = checked_table_size(nv + vertices_total, where + " vertices");
    const Index fine_nc = checked_table_size(table.children * nc, where + " cells");
    require(first_vertex.back() <= fine_nv, where + ": block vertex counts exceed the level's vertices");

    Mesh<dim> fine;
    fine.cell_type = type;
    fine.partial = true;
    fine.cells.resize(fine_nc, nvc);     // rows of the refined blocks only are written
    fine.vertices.resize(fine_nv, dim);  // rows of their vertices only
    // Fine vertex of every coarse vertex numbered by a refined block.
    const auto vertex_of = std::make_unique_for_overwrite<TableIndex[]>(static_cast<std::size_t>(nv));
    if (coarse_first_vertex.empty()) std::fill(vertex_of.get(), vertex_of.get() + nv, kUnknown);
    const Index row = table.children * nvc;  // table entries per coarse cell
    for (const auto& [b0, b1] : refined_runs) {
      prefault(fine.cells.data() + row * b0 * per_block,
               static_cast<std::size_t>(row * (b1 - b0) * per_block) * sizeof(TableIndex));
      for (int d = 0; d < dim; ++d)
        prefault(fine.vertices.data() + d * fine_nv + first_of(first_vertex, b0),
                 static_cast<std::size_t>(first_of(first_vertex, b1) - first_of(first_vertex, b0)) *
                     sizeof(double));
      if (!coarse_first_vertex.empty())
        std::fill(vertex_of.get() + first_of(coarse_first_vertex, b0),
                  vertex_of.get() + first_of(coarse_first_vertex, b1), kUnknown);
    }
    // Nodes the current block numbers (keyed by their coordinates in its base
    // cell), and those earlier blocks numbered on their boundaries.
    FlatNumbering numbered;
    BoundaryNodes boundary(nb);
    CellCoordinates coordinates(shape, k);
    for (const Index b : refined_blocks) {
      numbered.clear();
      TableIndex next = first_of(first_vertex, b);
      const Index c0 = b * per_block;
      for (Index i = 0; i < per_block; ++i) {
        const Index c = c0 + i;
        const std::array<Coords, 8>& x = coordinates.at(i);
        const TableIndex* v = &coarse.cells(c, 0);
        std::array<TableIndex, RefinementTable::kMaxNodes> local{};
        for (const int l : first_use) {
          const Coords y = shape.node(x, l);
          const Index owner = supports.of(b, shape.support(y, scale));
          TableIndex number = kUnknown;
          if (l < nvc) {  // a coarse vertex: its number is known where its owner was refined
            if (owner == b) {
              TableIndex& slot = vertex_of[static_cast<std::size_t>(v[l])];
              if (slot < 0) {
                slot = next++;
                for (int d = 0; d < dim; ++d) fine.vertices(slot, d) = coarse.vertices(v[l], d);
              }
              number = slot;
            } else if (in(refined, owner)) {
              number = vertex_of[static_cast<std::size_t>(v[l])];
            }
          } else if (owner == b) {  // an edge midpoint, face or cell centre new in b
            const auto [slot, fresh] = numbered.find_or_insert(key_of(y));
            if (fresh) {
              *slot = next++;
              // The average of its corners, summed in refine_uniformly's order.
              const std::vector<int>& corners = shape.node_corners[at(l)];
              bool known = true;
              for (int j : corners) known = known && v[j] >= 0;
              for (int d = 0; d < dim; ++d) {
                if (!known) {  // an outer cell of the refined ring: never present
                  fine.vertices(*slot, d) = nan;
                  continue;
                }
                double s = coarse.vertices(v[corners[0]], d);
                for (std::size_t j = 1; j < corners.size(); ++j) s += coarse.vertices(v[corners[j]], d);
                fine.vertices(*slot, d) = (1.0 / static_cast<double>(corners.size())) * s;
              }
            }
            number = *slot;
          } else if (in(refined, owner)) {
            number = boundary.find(owner, key_in(base, shape, b, owner, y, scale));
            if (number < 0)
              throw Error(where + ": block " + std::to_string(b) + " found no number for a node of block " +
                          std::to_string(owner) + " (internal error)");
          }
          local[at(l)] = number;
        }
        TableIndex* out = &fine.cells(table.children * c, 0);
        for (int ch = 0; ch < table.children; ++ch)
          for (int j = 0; j < nvc; ++j) out[nvc * ch + j] = local[at(table.child_nodes[at(ch)][at(j)])];
      }
      if (next != first_of(first_vertex, b + 1))
        throw Error(where + ": block " + std::to_string(b) +
                    " numbered a different count of vertices than its closed form (internal error)");
      boundary.keep(b, numbered, shape, scale);
    }

    // Boundary facets: fine facets children f … children f + children - 1
    // refine coarse facet f by the facet's table; those outside the present
    // blocks are rows of -1.
    const Index nbf = coarse.num_boundary_facets(), fc = facet_table.children;
    fine.boundary_facets.resize(fc * nbf, nfv);
    fine.boundary_facets.setConstant(kUnknown);
    fine.facet_tags.resize(static_cast<std::size_t>(fc * nbf));
    CellCoordinates facet_coordinates(facet_shape, k);
    const std::int64_t lift = shape.simplex ? 1 : scale;  // facet weights to cell weights
    for (Index f = 0; f < nbf; ++f) {
      for (Index ch = 0; ch < fc; ++ch)
        fine.facet_tags[static_cast<std::size_t>(fc * f + ch)] =
            coarse.facet_tags[static_cast<std::size_t>(f)];
      const Index f0 = f / facets_per_base, b = facet_cell[static_cast<std::size_t>(f0)];
      if (!in(near, b) || !coarse.has_facet(f)) continue;
      // The facet's nodes in its base facet, then in the base cell.
      const std::array<Coords, 8>& xf = facet_coordinates.at(f % facets_per_base);
      const std::array<int, 4>& place = facet_local[static_cast<std::size_t>(f0)];
      std::array<TableIndex, RefinementTable::kMaxNodes> node{};
      bool complete = true;
      for (int l = 0; l < facet_table.nodes() && complete; ++l) {
        const Weights wf = facet_shape.weights(facet_shape.node(xf, l), scale);
        Weights w{};
        for (int i = 0; i < nfv; ++i) w[at(place[at(i)])] = lift * wf[at(i)];
        const Coords y = shape.coordinates(w, scale);
        const Index owner = supports.of(b, shape.support(y, scale));
        TableIndex number = kUnknown;
        if (in(refined, owner))
          number = l < nfv ? vertex_of[static_cast<std::size_t>(coarse.boundary_facets(f, l))]
                           : boundary.find(owner, key_in(base, shape, b, owner, y, scale));
        node[at(l)] = number;
        complete = number >= 0;
      }
      if (!complete) continue;
      for (Index ch = 0; ch < fc; ++ch)
        for (int j = 0; j < nfv; ++j)
          fine.boundary_facets(fc * f + ch, j) =
              node[at(facet_table.child_nodes[static_cast<std::size_t>(ch)][at(j)])];
    }

    const Index fine_per_block = table.children * per_block;
    append_partial_level(h, base_level, std::move(fine), ring, base_owner, fine_per_block, first_vertex,
                         blocks);

    coarse_first_vertex = std::move(first_vertex);
    numbered_by = std::move(fine_numbered);
    per_block = fine_per_block;
    facets_per_base *= fc;
  }
}

template void refine_by_position(MeshHierarchy<2>&, const std::vector<int>&, int, int,
                                 std::vector<NestedBlocks>&);
template void refine_by_position(MeshHierarchy<3>&, const std::vector<int>&, int, int,
                                 std::vector<NestedBlocks>&);

}  // namespace warpfem::fem
