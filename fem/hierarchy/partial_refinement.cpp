#include "fem/hierarchy/partial_refinement.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/prefault.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"

namespace warpfem::fem {

namespace {

/// first[b] = count[0] + … + count[b - 1] (blocks + 1 entries).
std::vector<TableIndex> offsets(const std::vector<Index>& count, const std::string& what) {
  std::vector<TableIndex> first(count.size() + 1);
  Index sum = 0;
  for (std::size_t b = 0; b < count.size(); ++b) {
    first[b] = checked_table_size(sum, what);
    sum += count[b];
  }
  first.back() = checked_table_size(sum, what);
  return first;
}

/// The block whose range [first[b], first[b + 1]) holds `id`; -1 past the last block.
Index block_of(const std::vector<TableIndex>& first, Index id) {
  if (id < 0 || id >= first.back()) return -1;
  return static_cast<Index>(std::upper_bound(first.begin(), first.end(), id) - first.begin()) - 1;
}

/// What refining a level needs to know about it besides its Mesh.
struct CoarseLevel {
  // On the base level: the first block using every vertex and edge (-1: none).
  std::vector<Index> vertex_block, edge_block;
  // Above it: the blocks' vertex and edge ranges, the edges of the refined
  // cells and of the stored boundary facets.
  std::vector<TableIndex> first_vertex, first_edge;
  IndexTable cell_edge;
  std::vector<TableIndex> facet_edge;
  const EdgeNumbering* base_edges = nullptr;  // set on the base level
  Index num_edges = 0;

  /// The block using vertex v first; `hint`: a block to try first (O(1)), the
  /// block being refined, which most of its cells' vertices are new in.
  Index vertex_owner(Index v, Index hint = -1) const {
    if (v < 0) return -1;
    if (base_edges) return vertex_block[static_cast<std::size_t>(v)];
    return in_range(first_vertex, hint, v) ? hint : block_of(first_vertex, v);
  }
  Index edge_owner(Index e, Index hint = -1) const {
    if (e < 0) return -1;
    if (base_edges) return edge_block[static_cast<std::size_t>(e)];
    return in_range(first_edge, hint, e) ? hint : block_of(first_edge, e);
  }
  static bool in_range(const std::vector<TableIndex>& first, Index b, Index id) {
    return b >= 0 && id >= first[static_cast<std::size_t>(b)] && id < first[static_cast<std::size_t>(b + 1)];
  }
  Index edge(Index c, int j) const { return base_edges ? base_edges->cell_edge(c, j) : cell_edge(c, j); }
  Index facet(Index f, Index a, Index b) const {
    return base_edges ? base_edges->boundary_facet_edge(f, a, b) : facet_edge[static_cast<std::size_t>(f)];
  }
};

constexpr TableIndex kUnknown = -1;

void refine_triangles(MeshHierarchy<2>& h, const EdgeNumbering& base_edges,
                      const std::vector<int>& base_owner, int rank, int levels_above,
                      std::vector<NestedBlocks>& blocks) {
  const int base_level = h.num_levels() - 1;
  h.levels.reserve(h.levels.size() + static_cast<std::size_t>(levels_above));  // references stay valid
  h.transfers.reserve(h.transfers.size() + static_cast<std::size_t>(levels_above));
  const Mesh<2>& base = h.levels.back();
  require(base.cell_type == CellType::triangle && !base.partial,
          "refine_partially: the base level must be a whole triangle mesh");
  const Index nb = base.num_cells();
  require(static_cast<Index>(base_owner.size()) == nb && base_edges.num_cells() == nb,
          "refine_partially: owners or edges do not belong to the base level");

  // 1. The vertices and edges every block uses first on the base level.
  CoarseLevel level;
  level.base_edges = &base_edges;
  level.num_edges = base_edges.num_edges();
  level.vertex_block.assign(static_cast<std::size_t>(base.num_vertices()), -1);
  level.edge_block.assign(static_cast<std::size_t>(level.num_edges), -1);
  std::vector<Index> new_vertices(static_cast<std::size_t>(nb), 0),
      new_edges(static_cast<std::size_t>(nb), 0);
  for (Index b = 0; b < nb; ++b)
    for (int k = 0; k < 3; ++k) {
      if (Index& o = level.vertex_block[static_cast<std::size_t>(base.cells(b, k))]; o < 0)
        o = b, ++new_vertices[static_cast<std::size_t>(b)];
      if (Index& o = level.edge_block[static_cast<std::size_t>(base_edges.cell_edge(b, k))]; o < 0)
        o = b, ++new_edges[static_cast<std::size_t>(b)];
    }

  // The block of every boundary facet (the one cell at its edge).
  std::vector<Index> facet_block(static_cast<std::size_t>(base.num_boundary_facets()));
  for (Index f = 0; f < base.num_boundary_facets(); ++f)
    facet_block[static_cast<std::size_t>(f)] = level.edge_block[static_cast<std::size_t>(
        base_edges.boundary_facet_edge(f, base.boundary_facets(f, 0), base.boundary_facets(f, 1)))];

  // 2. The blocks this rank refines: its own, their neighbours (present), and
  // one more ring (so that every present cell's vertices get their numbers).
  std::vector<char> own(static_cast<std::size_t>(nb), 0);
  for (Index b = 0; b < nb; ++b)
    own[static_cast<std::size_t>(b)] = base_owner[static_cast<std::size_t>(b)] == rank;
  const std::vector<char> near = blocks_sharing_a_vertex(base.cells, own),
                          refined = blocks_sharing_a_vertex(base.cells, near);
  std::vector<Index> near_blocks, refined_blocks;
  for (Index b = 0; b < nb; ++b) {
    if (near[static_cast<std::size_t>(b)]) near_blocks.push_back(b);
    if (refined[static_cast<std::size_t>(b)]) refined_blocks.push_back(b);
  }
  // Runs [b0, b1) of consecutive refined blocks: the arrays every block writes
  // are populated run by run, one system call each (a single block's share is
  // below prefault()'s megabyte and would be faulted in page by page).
  const std::vector<std::array<Index, 2>> refined_runs = block_cell_ranges(refined_blocks, 1);
  const auto in = [](const std::vector<char>& mask, Index b) {
    return b >= 0 && mask[static_cast<std::size_t>(b)];
  };

  const double nan = std::numeric_limits<double>::quiet_NaN();
  Index per_block = 1;  // cells per block on the coarse level
  for (int k = 1; k <= levels_above; ++k) {
    const Mesh<2>& coarse = h.levels.back();
    const bool more = k < levels_above;  // the fine level's edges are needed
    const Index nv = coarse.num_vertices(), ne = level.num_edges, nc = coarse.num_cells();
    const std::string where = "refine_partially: level " + std::to_string(base_level + k);
    // What every block uses first on the fine level, and where its ranges start.
    std::vector<Index> fine_vertices(static_cast<std::size_t>(nb)), fine_edges(static_cast<std::size_t>(nb));
    for (std::size_t b = 0; b < static_cast<std::size_t>(nb); ++b) {
      fine_vertices[b] = new_vertices[b] + new_edges[b];
      fine_edges[b] = 2 * new_edges[b] + 3 * per_block;
    }
    std::vector<TableIndex> first_vertex = offsets(fine_vertices, where + " vertices");
    std::vector<TableIndex> first_edge = offsets(fine_edges, where + " edges");
    const Index fine_nv = checked_table_size(nv + ne, where + " vertices");
    const Index fine_nc = checked_table_size(4 * nc, where + " cells");
    const Index fine_ne = checked_table_size(2 * ne + 3 * nc, where + " edges");
    require(first_vertex.back() <= fine_nv, where + ": block vertex counts exceed the level's vertices");

    Mesh<2> fine;
    fine.cell_type = CellType::triangle;
    fine.partial = true;
    fine.cells.resize(fine_nc, 3);     // rows of the refined blocks only are written
    fine.vertices.resize(fine_nv, 2);  // rows of their vertices only
    IndexTable fine_cell_edge;
    if (more) fine_cell_edge.resize(fine_nc, 3);
    // Fine vertex of every coarse node (vertex v, midpoint of edge e at nv + e)
    // and fine edge of every key (half of coarse edge E at its smaller vertex
    // 2E, at the other 2E + 1; edge j inside coarse cell c 2ne + 3c + j), as
    // number_fine_edges() keys them; unwritten outside the refined blocks.
    const auto vertex_of = std::make_unique_for_overwrite<TableIndex[]>(static_cast<std::size_t>(nv + ne));
    const auto id_of_key =
        more ? std::make_unique_for_overwrite<TableIndex[]>(static_cast<std::size_t>(2 * ne + 3 * nc))
             : nullptr;
    if (level.base_edges) {  // the base level is small and not numbered by block: all of it
      std::fill(vertex_of.get(), vertex_of.get() + nv + ne, kUnknown);
      if (more) std::fill(id_of_key.get(), id_of_key.get() + 2 * ne, kUnknown);
    }
    // The fine number of a coarse node used by a cell of block b: new in b
    // (numbered on first use), or numbered by the earlier block that used it
    // first, if that one was refined.
    const auto known = [&](Index owner, const TableIndex* slot) {
      return in(refined, owner) ? *slot : kUnknown;
    };

    const auto populate = [](auto* data, Index begin, Index end) {
      prefault(data + begin, static_cast<std::size_t>(end - begin) * sizeof(*data));
    };
    const auto at = [](const std::vector<TableIndex>& first, Index b) {
      return first[static_cast<std::size_t>(b)];
    };
    for (const auto& [b0, b1] : refined_runs) {
      populate(fine.cells.data(), 12 * b0 * per_block, 12 * b1 * per_block);
      populate(fine.vertices.data(), at(first_vertex, b0), at(first_vertex, b1));
      populate(fine.vertices.data() + fine_nv, at(first_vertex, b0), at(first_vertex, b1));
      if (more) {
        populate(fine_cell_edge.data(), 12 * b0 * per_block, 12 * b1 * per_block);
        populate(id_of_key.get() + 2 * ne, 3 * b0 * per_block, 3 * b1 * per_block);
      }
      if (level.base_edges) continue;  // the base level's tables are filled whole above
      populate(vertex_of.get(), at(level.first_vertex, b0), at(level.first_vertex, b1));
      populate(vertex_of.get() + nv, at(level.first_edge, b0), at(level.first_edge, b1));
      if (more) populate(id_of_key.get(), 2 * at(level.first_edge, b0), 2 * at(level.first_edge, b1));
    }
    for (Index b = 0; b < nb; ++b) {
      if (!in(refined, b)) continue;
      const Index c0 = b * per_block, c1 = c0 + per_block;
      if (!level.base_edges) {
        std::fill(vertex_of.get() + level.first_vertex[static_cast<std::size_t>(b)],
                  vertex_of.get() + level.first_vertex[static_cast<std::size_t>(b + 1)], kUnknown);
        std::fill(vertex_of.get() + nv + level.first_edge[static_cast<std::size_t>(b)],
                  vertex_of.get() + nv + level.first_edge[static_cast<std::size_t>(b + 1)], kUnknown);
        if (more)
          std::fill(id_of_key.get() + 2 * level.first_edge[static_cast<std::size_t>(b)],
                    id_of_key.get() + 2 * level.first_edge[static_cast<std::size_t>(b + 1)], kUnknown);
      }
      if (more) std::fill(id_of_key.get() + 2 * ne + 3 * c0, id_of_key.get() + 2 * ne + 3 * c1, kUnknown);
      TableIndex next_vertex = first_vertex[static_cast<std::size_t>(b)];
      TableIndex next_edge = first_edge[static_cast<std::size_t>(b)];
      // Vertex positions written column by column (Points are stored x then y).
      const double* cx = coarse.vertices.data();
      const double* cy = cx + nv;
      double* fx = fine.vertices.data();
      double* fy = fx + fine_nv;
      for (Index c = c0; c < c1; ++c) {
        const TableIndex* v = &coarse.cells(c, 0);
        const Index e[3] = {level.edge(c, 0), level.edge(c, 1), level.edge(c, 2)};
        // Which of the cell's nodes block b uses first (the rest were numbered
        // by an earlier block: looked up, rarely, on block boundaries).
        const bool vertex_new[3] = {level.vertex_owner(v[0], b) == b, level.vertex_owner(v[1], b) == b,
                                    level.vertex_owner(v[2], b) == b};
        const bool edge_new[3] = {level.edge_owner(e[0], b) == b, level.edge_owner(e[1], b) == b,
                                  level.edge_owner(e[2], b) == b};
        const auto vertex_node = [&](int j) -> TableIndex {
          const Index x = v[j];
          if (!vertex_new[j]) return known(level.vertex_owner(x), vertex_of.get() + x);
          TableIndex& slot = vertex_of[static_cast<std::size_t>(x)];
          if (slot < 0) {
            slot = next_vertex++;
            fx[slot] = cx[x];
            fy[slot] = cy[x];
          }
          return slot;
        };
        const auto edge_node = [&](int j) -> TableIndex {  // local edge j: vertices j, j + 1
          if (!edge_new[j]) return known(level.edge_owner(e[j]), vertex_of.get() + nv + e[j]);
          TableIndex& slot = vertex_of[static_cast<std::size_t>(nv + e[j])];
          if (slot < 0) {
            slot = next_vertex++;
            const Index p = v[j], q = v[(j + 1) % 3];
            if (p >= 0 && q >= 0) {
              fx[slot] = 0.5 * (cx[p] + cx[q]);
              fy[slot] = 0.5 * (cy[p] + cy[q]);
            } else {
              fx[slot] = fy[slot] = nan;  // an outer cell of the refined ring
            }
          }
          return slot;
        };
        // The order refine_uniformly uses them first: v0 m01 m20 v1 m12 v2.
        const TableIndex v0 = vertex_node(0), m01 = edge_node(0), m20 = edge_node(2), v1 = vertex_node(1),
                         m12 = edge_node(1), v2 = vertex_node(2);
        const TableIndex children[12] = {v0, m01, m20, m01, v1, m12, m20, m12, v2, m01, m12, m20};
        std::copy(children, children + 12, &fine.cells(4 * c, 0));
        if (!more) continue;
        // The fine edges, as number_fine_edges() numbers them. The halves of
        // coarse edge E have keys 2E (at its smaller vertex number) and 2E + 1.
        // In an outer cell of the refined ring an endpoint may have no number;
        // the halves are then told apart by this cell's vertex order, which
        // keeps the block's count exact (every cell uses both halves of its
        // edges) though the two may swap there: such cells and their
        // descendants stay outside the present ones.
        const auto fine_edge = [&](Index key, bool is_new) -> TableIndex {
          if (key < 0) return kUnknown;
          TableIndex& slot = id_of_key[static_cast<std::size_t>(key)];
          if (!is_new) return known(level.edge_owner(key / 2), &slot);
          return slot >= 0 ? slot : (slot = next_edge++);
        };
        const auto half = [&](int j, bool at_first) -> TableIndex {
          const Index p = v[j], q = v[(j + 1) % 3];
          if (e[j] < 0) return kUnknown;
          const bool first_is_lower = (p < 0 || q < 0) ? true : p < q;
          return fine_edge(2 * e[j] + (at_first == first_is_lower ? 0 : 1), edge_new[j]);
        };
        const Index ka = 2 * ne + 3 * c;
        TableIndex* out = &fine_cell_edge(4 * c, 0);
        // Children 0..3, local edges (0,1), (1,2), (2,0), in the order of first use.
        out[0] = half(0, true);
        out[1] = fine_edge(ka + 2, true);
        out[2] = half(2, false);
        out[3] = half(0, false);
        out[4] = half(1, true);
        out[5] = fine_edge(ka, true);
        out[6] = fine_edge(ka + 1, true);
        out[7] = half(1, false);
        out[8] = half(2, true);
        out[9] = fine_edge(ka, true);
        out[10] = fine_edge(ka + 1, true);
        out[11] = fine_edge(ka + 2, true);
      }
      if (next_vertex != first_vertex[static_cast<std::size_t>(b + 1)] ||
          (more && next_edge != first_edge[static_cast<std::size_t>(b + 1)]))
        throw Error(where + ": block " + std::to_string(b) +
                    " numbered a different count of vertices or edges than its closed form (internal error)");
    }

    // Boundary facets: fine facets 2f, 2f + 1 halve coarse facet f at its first
    // and second vertex; those outside the present blocks are (-1, -1).
    const Index nbf = coarse.num_boundary_facets();
    fine.boundary_facets.resize(2 * nbf, 2);
    fine.facet_tags.resize(static_cast<std::size_t>(2 * nbf));
    std::vector<TableIndex> fine_facet_edge(more ? static_cast<std::size_t>(2 * nbf) : 0, kUnknown);
    std::vector<Index> fine_facet_block(static_cast<std::size_t>(2 * nbf));
    for (Index f = 0; f < nbf; ++f) {
      fine.facet_tags[static_cast<std::size_t>(2 * f)] =
          fine.facet_tags[static_cast<std::size_t>(2 * f + 1)] =
              coarse.facet_tags[static_cast<std::size_t>(f)];
      fine_facet_block[static_cast<std::size_t>(2 * f)] =
          fine_facet_block[static_cast<std::size_t>(2 * f + 1)] = facet_block[static_cast<std::size_t>(f)];
      fine.boundary_facets.row(2 * f).setConstant(kUnknown);
      fine.boundary_facets.row(2 * f + 1).setConstant(kUnknown);
      const Index a = coarse.boundary_facets(f, 0), c = coarse.boundary_facets(f, 1);
      if (!in(near, facet_block[static_cast<std::size_t>(f)]) || a < 0 || c < 0) continue;
      const Index E = level.facet(f, a, c);
      const Index owner = level.edge_owner(E);
      const TableIndex fa = known(level.vertex_owner(a), vertex_of.get() + a);
      const TableIndex fc = known(level.vertex_owner(c), vertex_of.get() + c);
      const TableIndex fm = E < 0 ? kUnknown : known(owner, vertex_of.get() + nv + E);
      if (fa < 0 || fc < 0 || fm < 0) continue;
      fine.boundary_facets.row(2 * f) << fa, fm;
      fine.boundary_facets.row(2 * f + 1) << fm, fc;
      if (more) {
        const Index lo = std::min(a, c);
        fine_facet_edge[static_cast<std::size_t>(2 * f)] =
            id_of_key[static_cast<std::size_t>(2 * E + (a == lo ? 0 : 1))];
        fine_facet_edge[static_cast<std::size_t>(2 * f + 1)] =
            id_of_key[static_cast<std::size_t>(2 * E + (c == lo ? 0 : 1))];
      }
    }

    // The present cells: those of the rank's blocks and their neighbours.
    const Index fine_per_block = 4 * per_block;
    fine.present_cells = block_cell_ranges(near_blocks, fine_per_block);

    NestedBlocks nested;
    nested.base_cells = &h.levels[static_cast<std::size_t>(base_level)].cells;
    nested.owner = base_owner;
    nested.cells_per_block = fine_per_block;
    nested.first_vertex = first_vertex;
    blocks.push_back(std::move(nested));
    h.transfers.emplace_back();  // the parent layout only (RefinedMesh::parent_of)
    h.levels.push_back(std::move(fine));

    // The fine level is the next one's coarse level.
    level.base_edges = nullptr;
    level.vertex_block.clear();
    level.edge_block.clear();
    level.first_vertex = std::move(first_vertex);
    level.first_edge = std::move(first_edge);
    level.cell_edge = std::move(fine_cell_edge);
    level.facet_edge = std::move(fine_facet_edge);
    level.num_edges = fine_ne;
    facet_block = std::move(fine_facet_block);
    new_vertices = std::move(fine_vertices);
    new_edges = std::move(fine_edges);
    per_block = fine_per_block;
  }
}

// ---- Tetrahedra: nodes identified by their position in the base cell -------

/// Barycentric coordinates of a point in its base cell, scaled by 2^k on level
/// base + k (integers: every vertex of a uniform refinement sits there).
using Bary = std::array<std::int32_t, 4>;

/// splitmix64's finalizer: the hash of a 64-bit key.
std::uint64_t mix(std::uint64_t x) {
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
struct MixHash {
  std::size_t operator()(std::uint64_t k) const { return static_cast<std::size_t>(mix(k)); }
};

/// Node number by key, open addressing with linear probing: one flat array
/// (the node-based std::unordered_map spent most of the refinement chasing
/// and allocating nodes). clear() keeps the capacity.
template <class Key, class Hash>
class FlatNumbering {
 public:
  /// The number stored for `key`, and whether it was absent (then kEmpty, to be set).
  std::pair<TableIndex*, bool> find_or_insert(const Key& key) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    std::size_t i = Hash{}(key) & (slots_.size() - 1);
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
    Key key{};
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

int support_mask(const Bary& x) {
  int mask = 0;
  for (int j = 0; j < 4; ++j) mask |= x[static_cast<std::size_t>(j)] != 0 ? 1 << j : 0;
  return mask;
}

/// What refine_tetrahedra needs of the base level: the first cell around every
/// sub-simplex (vertex, edge, face, the cell itself) of every base cell, the
/// block that numbers a node lying inside that sub-simplex.
struct BaseSupports {
  std::vector<std::array<Index, 16>> owner;  // [cell][mask of its local vertices]
  // The cells around vertex v: around[start[v]] … around[start[v + 1] - 1], increasing.
  std::vector<TableIndex> start;
  std::vector<Index> around;

  explicit BaseSupports(const Mesh<3>& base) {
    const Index nc = base.num_cells(), nv = base.num_vertices();
    start.assign(static_cast<std::size_t>(nv) + 1, 0);
    for (Index c = 0; c < nc; ++c)
      for (int j = 0; j < 4; ++j) ++start[static_cast<std::size_t>(base.cells(c, j)) + 1];
    for (Index v = 0; v < nv; ++v)
      start[static_cast<std::size_t>(v + 1)] += start[static_cast<std::size_t>(v)];
    around.resize(static_cast<std::size_t>(start.back()));
    std::vector<TableIndex> fill(start.begin(), start.end() - 1);
    for (Index c = 0; c < nc; ++c)  // increasing cells: each vertex's list is sorted
      for (int j = 0; j < 4; ++j)
        around[static_cast<std::size_t>(fill[static_cast<std::size_t>(base.cells(c, j))]++)] = c;
    const auto contains = [&](Index c, Index v) {
      for (int j = 0; j < 4; ++j)
        if (base.cells(c, j) == v) return true;
      return false;
    };
    owner.resize(static_cast<std::size_t>(nc));
    for (Index c = 0; c < nc; ++c)
      for (int mask = 1; mask < 16; ++mask) {
        const int lowest = std::countr_zero(static_cast<unsigned>(mask));
        const Index v0 = base.cells(c, lowest);
        Index first = c;
        for (TableIndex i = start[static_cast<std::size_t>(v0)]; i < start[static_cast<std::size_t>(v0 + 1)];
             ++i) {
          const Index d = around[static_cast<std::size_t>(i)];
          bool all = true;
          for (int j = lowest + 1; j < 4 && all; ++j)
            if (mask & (1 << j)) all = contains(d, base.cells(c, j));
          if (all) {
            first = d;
            break;
          }
        }
        owner[static_cast<std::size_t>(c)][static_cast<std::size_t>(mask)] = first;
      }
  }
  Index of(Index cell, int mask) const {
    return owner[static_cast<std::size_t>(cell)][static_cast<std::size_t>(mask)];
  }
};

/// A node's coordinates in base cell `to` (16 bits each, in its vertex order)
/// from those in base cell `from`, which shares the node's support with it:
/// the key under which `to`, the node's owner, numbered it.
std::uint64_t key_in(const Mesh<3>& base, Index from, Index to, const Bary& y) {
  Bary z{};
  for (int j = 0; j < 4; ++j)
    if (y[static_cast<std::size_t>(j)] != 0)
      for (int i = 0; i < 4; ++i)
        if (base.cells(to, i) == base.cells(from, j))
          z[static_cast<std::size_t>(i)] = y[static_cast<std::size_t>(j)];
  std::uint64_t key = 0;
  for (int d = 0; d < 4; ++d) key = key << 16 | static_cast<std::uint64_t>(z[static_cast<std::size_t>(d)]);
  return key;
}

/// The edge midpoints on its boundary that each refined block numbered,
/// sorted by key_in(owner) (read by the blocks after it).
class BoundaryNodes {
 public:
  explicit BoundaryNodes(Index blocks) : range_(static_cast<std::size_t>(blocks), {0, 0}) {}
  /// Keeps the boundary nodes of `block`, numbered in `numbers` (keys in its coordinates).
  void keep(Index block, const FlatNumbering<std::uint64_t, MixHash>& numbers) {
    const std::size_t begin = nodes_.size();
    numbers.for_each([&](std::uint64_t key, TableIndex number) {
      // Inside the block (all four coordinates non-zero) nobody else looks.
      bool inside = true;
      for (int d = 0; d < 4; ++d) inside = inside && ((key >> (16 * d)) & 0xFFFF) != 0;
      if (!inside) nodes_.push_back({key, number});
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
  CellCoordinates(const RefinementTable& t, int depth, int facet_vertices)
      : t_(t),
        depth_(depth),
        n_(facet_vertices),
        digits_(static_cast<std::size_t>(depth), -1),
        stack_(static_cast<std::size_t>(depth) + 1) {
    for (int j = 0; j < 4; ++j) {
      stack_[0][static_cast<std::size_t>(j)].fill(0);
      if (j < n_) stack_[0][static_cast<std::size_t>(j)][static_cast<std::size_t>(j)] = 1;
    }
  }
  /// Cell i of its block (i in [0, children^depth)): its vertices' coordinates.
  const std::array<Bary, 4>& at(Index i) {
    int changed = depth_;
    for (int d = depth_ - 1; d >= 0; --d, i /= t_.children) {
      const int q = static_cast<int>(i % t_.children);
      if (digits_[static_cast<std::size_t>(d)] != q) changed = d, digits_[static_cast<std::size_t>(d)] = q;
    }
    for (int d = changed; d < depth_; ++d) {
      const auto& parent = stack_[static_cast<std::size_t>(d)];
      auto& child = stack_[static_cast<std::size_t>(d) + 1];
      const int q = digits_[static_cast<std::size_t>(d)];
      for (int j = 0; j < n_; ++j)
        child[static_cast<std::size_t>(j)] =
            node(parent, t_.child_nodes[static_cast<std::size_t>(q)][static_cast<std::size_t>(j)]);
    }
    return stack_[static_cast<std::size_t>(depth_)];
  }
  /// Local node `l` (vertex or edge midpoint) of a cell with vertices at `x`,
  /// at twice the scale.
  Bary node(const std::array<Bary, 4>& x, int l) const {
    Bary out{};
    if (l < t_.vertices) {
      for (int d = 0; d < 4; ++d)
        out[static_cast<std::size_t>(d)] = 2 * x[static_cast<std::size_t>(l)][static_cast<std::size_t>(d)];
    } else {
      const auto& e =
          cell_edges(t_.vertices == 3 ? CellType::triangle
                                      : CellType::tetrahedron)[static_cast<std::size_t>(l - t_.vertices)];
      for (int d = 0; d < 4; ++d)
        out[static_cast<std::size_t>(d)] = x[static_cast<std::size_t>(e[0])][static_cast<std::size_t>(d)] +
                                           x[static_cast<std::size_t>(e[1])][static_cast<std::size_t>(d)];
    }
    return out;
  }

 private:
  const RefinementTable& t_;
  int depth_, n_;
  std::vector<int> digits_;
  std::vector<std::array<Bary, 4>> stack_;
};

/// Bey's refinement of the levels above a whole tetrahedral base level, only
/// around `rank`'s blocks. Unlike refine_triangles, no edge numbering is
/// carried from level to level: a node (coarse vertex or edge midpoint) is
/// named by its integer barycentric coordinates in its base cell, which every
/// cell can compute from its place in the hierarchy alone. The block that
/// numbers it first is the first base cell around the sub-simplex holding it
/// (its descendants come first in cell order). Counts per block follow from
/// the base level: new vertices V' = V + E, edges E' = 2E + 3F + C (halves,
/// three inside each face, Bey's interior diagonal), faces F' = 4F + 8C.
void refine_tetrahedra(MeshHierarchy<3>& h, const std::vector<int>& base_owner, int rank, int levels_above,
                       std::vector<NestedBlocks>& blocks) {
  const int base_level = h.num_levels() - 1;
  h.levels.reserve(h.levels.size() + static_cast<std::size_t>(levels_above));  // references stay valid
  h.transfers.reserve(h.transfers.size() + static_cast<std::size_t>(levels_above));
  const Mesh<3>& base = h.levels.back();
  require(base.cell_type == CellType::tetrahedron && !base.partial,
          "refine_partially: the base level must be a whole tetrahedral mesh");
  require(levels_above <= 15, "refine_partially: at most 15 levels above the base level");
  const Index nb = base.num_cells();
  require(static_cast<Index>(base_owner.size()) == nb,
          "refine_partially: owners do not belong to the base level");
  const RefinementTable& table = refinement_table(CellType::tetrahedron);
  const RefinementTable& facet_table = refinement_table(CellType::triangle);
  const auto& tet_edges = cell_edges(CellType::tetrahedron);
  const auto& tri_edges = cell_edges(CellType::triangle);
  // The local nodes in the order a cell's children first use them.
  std::vector<int> first_use;
  {
    std::array<bool, RefinementTable::kMaxNodes> seen{};
    for (int k = 0; k < table.children; ++k)
      for (int j = 0; j < table.vertices; ++j)
        if (const int n = table.child_nodes[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)];
            !seen[static_cast<std::size_t>(n)])
          seen[static_cast<std::size_t>(n)] = true, first_use.push_back(n);
  }

  // 1. Who numbers what on the base level, and how much each block numbers.
  const BaseSupports supports(base);
  std::vector<Index> new_vertices(static_cast<std::size_t>(nb), 0),
      new_edges(static_cast<std::size_t>(nb), 0), new_faces(static_cast<std::size_t>(nb), 0);
  for (Index b = 0; b < nb; ++b)
    for (int mask = 1; mask < 15; ++mask) {
      if (supports.of(b, mask) != b) continue;
      const int count = std::popcount(static_cast<unsigned>(mask));
      (count == 1 ? new_vertices : count == 2 ? new_edges : new_faces)[static_cast<std::size_t>(b)] += 1;
    }
  // Every base boundary facet: the cell it bounds and its vertices' places there.
  const Index nbf0 = base.num_boundary_facets();
  std::vector<Index> facet_cell(static_cast<std::size_t>(nbf0), -1);
  std::vector<std::array<int, 3>> facet_local(static_cast<std::size_t>(nbf0));
  for (Index f = 0; f < nbf0; ++f) {
    // The face's first cell is the only one it bounds.
    const TableIndex* v = &base.boundary_facets(f, 0);
    for (TableIndex i = supports.start[static_cast<std::size_t>(v[0])];
         i < supports.start[static_cast<std::size_t>(v[0]) + 1] &&
         facet_cell[static_cast<std::size_t>(f)] < 0;
         ++i) {
      const Index c = supports.around[static_cast<std::size_t>(i)];
      std::array<int, 3> local{-1, -1, -1};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
          if (base.cells(c, j) == v[i]) local[static_cast<std::size_t>(i)] = j;
      if (local[0] >= 0 && local[1] >= 0 && local[2] >= 0)
        facet_cell[static_cast<std::size_t>(f)] = c, facet_local[static_cast<std::size_t>(f)] = local;
    }
    require(facet_cell[static_cast<std::size_t>(f)] >= 0,
            "refine_partially: boundary facet " + std::to_string(f) + " is not a face of a cell");
  }

  // 2. The blocks this rank refines (as refine_triangles).
  std::vector<char> own(static_cast<std::size_t>(nb), 0);
  for (Index b = 0; b < nb; ++b)
    own[static_cast<std::size_t>(b)] = base_owner[static_cast<std::size_t>(b)] == rank;
  const std::vector<char> near = blocks_sharing_a_vertex(base.cells, own),
                          refined = blocks_sharing_a_vertex(base.cells, near);
  std::vector<Index> near_blocks, refined_blocks;
  for (Index b = 0; b < nb; ++b) {
    if (near[static_cast<std::size_t>(b)]) near_blocks.push_back(b);
    if (refined[static_cast<std::size_t>(b)]) refined_blocks.push_back(b);
  }
  const std::vector<std::array<Index, 2>> refined_runs = block_cell_ranges(refined_blocks, 1);
  const auto in = [](const std::vector<char>& mask, Index b) {
    return b >= 0 && mask[static_cast<std::size_t>(b)];
  };
  const auto at = [](const std::vector<TableIndex>& first, Index b) {
    return first[static_cast<std::size_t>(b)];
  };

  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<TableIndex> coarse_first_vertex;  // empty on the base level (all its vertices are known)
  Index per_block = 1;
  for (int k = 0; k < levels_above; ++k) {
    const Mesh<3>& coarse = h.levels.back();
    const Index nv = coarse.num_vertices(), nc = coarse.num_cells();
    const std::string where = "refine_partially: level " + std::to_string(base_level + k + 1);
    std::vector<Index> fine_vertices(static_cast<std::size_t>(nb)), fine_edges(static_cast<std::size_t>(nb)),
        fine_faces(static_cast<std::size_t>(nb));
    for (std::size_t b = 0; b < static_cast<std::size_t>(nb); ++b) {
      fine_vertices[b] = new_vertices[b] + new_edges[b];
      fine_edges[b] = 2 * new_edges[b] + 3 * new_faces[b] + per_block;
      fine_faces[b] = 4 * new_faces[b] + 8 * per_block;
    }
    std::vector<TableIndex> first_vertex = offsets(fine_vertices, where + " vertices");
    Index edges_total = 0;
    for (Index e : new_edges) edges_total += e;
    const Index fine_nv = checked_table_size(nv + edges_total, where + " vertices");
    const Index fine_nc = checked_table_size(8 * nc, where + " cells");
    require(first_vertex.back() <= fine_nv, where + ": block vertex counts exceed the level's vertices");

    Mesh<3> fine;
    fine.cell_type = CellType::tetrahedron;
    fine.partial = true;
    fine.cells.resize(fine_nc, 4);     // rows of the refined blocks only are written
    fine.vertices.resize(fine_nv, 3);  // rows of their vertices only
    // Fine vertex of every coarse vertex numbered by a refined block.
    const auto vertex_of = std::make_unique_for_overwrite<TableIndex[]>(static_cast<std::size_t>(nv));
    if (coarse_first_vertex.empty()) std::fill(vertex_of.get(), vertex_of.get() + nv, kUnknown);
    for (const auto& [b0, b1] : refined_runs) {
      prefault(fine.cells.data() + 32 * b0 * per_block,
               static_cast<std::size_t>(32 * (b1 - b0) * per_block) * sizeof(TableIndex));
      for (int d = 0; d < 3; ++d)
        prefault(fine.vertices.data() + d * fine_nv + at(first_vertex, b0),
                 static_cast<std::size_t>(at(first_vertex, b1) - at(first_vertex, b0)) * sizeof(double));
      if (!coarse_first_vertex.empty())
        std::fill(vertex_of.get() + at(coarse_first_vertex, b0),
                  vertex_of.get() + at(coarse_first_vertex, b1), kUnknown);
    }
    // Edge midpoints the current block numbers (keyed by their coordinates in
    // its base cell), and those earlier blocks numbered on their boundaries.
    FlatNumbering<std::uint64_t, MixHash> numbered;
    BoundaryNodes boundary(nb);
    CellCoordinates coordinates(table, k, 4);
    for (const Index b : refined_blocks) {
      numbered.clear();
      TableIndex next = at(first_vertex, b);
      const Index c0 = b * per_block;
      for (Index i = 0; i < per_block; ++i) {
        const Index c = c0 + i;
        const std::array<Bary, 4>& x = coordinates.at(i);
        const TableIndex* v = &coarse.cells(c, 0);
        std::array<TableIndex, RefinementTable::kMaxNodes> local{};
        for (const int l : first_use) {
          const Bary y = coordinates.node(x, l);
          const int mask = support_mask(y);
          const Index owner = supports.of(b, mask);
          TableIndex number = kUnknown;
          if (l < 4) {  // a coarse vertex: its number is known where its owner was refined
            if (owner == b) {
              TableIndex& slot = vertex_of[static_cast<std::size_t>(v[l])];
              if (slot < 0) {
                slot = next++;
                for (int d = 0; d < 3; ++d) fine.vertices(slot, d) = coarse.vertices(v[l], d);
              }
              number = slot;
            } else if (in(refined, owner)) {
              number = vertex_of[static_cast<std::size_t>(v[l])];
            }
          } else {  // an edge midpoint
            const auto& e = tet_edges[static_cast<std::size_t>(l - 4)];
            const auto create = [&](TableIndex& slot) {
              slot = next++;
              const Index p = v[e[0]], q = v[e[1]];
              for (int d = 0; d < 3; ++d)
                fine.vertices(slot, d) =
                    p >= 0 && q >= 0 ? 0.5 * (coarse.vertices(p, d) + coarse.vertices(q, d)) : nan;
            };
            if (owner == b) {
              std::uint64_t key = 0;
              for (int d = 0; d < 4; ++d)
                key = key << 16 | static_cast<std::uint64_t>(y[static_cast<std::size_t>(d)]);
              const auto [slot, fresh] = numbered.find_or_insert(key);
              if (fresh) create(*slot);
              number = *slot;
            } else if (in(refined, owner)) {
              number = boundary.find(owner, key_in(base, b, owner, y));
              if (number < 0)
                throw Error(where + ": block " + std::to_string(b) + " found no number for a node of block " +
                            std::to_string(owner) + " (internal error)");
            }
          }
          local[static_cast<std::size_t>(l)] = number;
        }
        TableIndex* out = &fine.cells(8 * c, 0);
        for (int ch = 0; ch < 8; ++ch)
          for (int j = 0; j < 4; ++j)
            out[4 * ch + j] = local[static_cast<std::size_t>(
                table.child_nodes[static_cast<std::size_t>(ch)][static_cast<std::size_t>(j)])];
      }
      if (next != at(first_vertex, b + 1))
        throw Error(where + ": block " + std::to_string(b) +
                    " numbered a different count of vertices than its closed form (internal error)");
      boundary.keep(b, numbered);
    }

    // Boundary facets: fine facets 4f … 4f + 3 refine coarse facet f by the
    // triangle table; those outside the present blocks are rows of -1.
    const Index nbf = coarse.num_boundary_facets();
    fine.boundary_facets.resize(4 * nbf, 3);
    fine.boundary_facets.setConstant(kUnknown);
    fine.facet_tags.resize(static_cast<std::size_t>(4 * nbf));
    Index facets_per_base = 1;
    for (int d = 0; d < k; ++d) facets_per_base *= 4;
    CellCoordinates facet_coordinates(facet_table, k, 3);
    for (Index f = 0; f < nbf; ++f) {
      for (int ch = 0; ch < 4; ++ch)
        fine.facet_tags[static_cast<std::size_t>(4 * f + ch)] =
            coarse.facet_tags[static_cast<std::size_t>(f)];
      const Index f0 = f / facets_per_base, b = facet_cell[static_cast<std::size_t>(f0)];
      if (!in(near, b) || !coarse.has_facet(f)) continue;
      // The facet's vertices in its base facet, then in the base cell.
      const std::array<Bary, 4>& xf = facet_coordinates.at(f % facets_per_base);
      const std::array<int, 3>& place = facet_local[static_cast<std::size_t>(f0)];
      std::array<Bary, 4> x{};
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          x[static_cast<std::size_t>(j)][static_cast<std::size_t>(place[static_cast<std::size_t>(i)])] =
              xf[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)];
      std::array<TableIndex, 6> node{};
      bool complete = true;
      for (int l = 0; l < 6 && complete; ++l) {
        Bary y{};
        for (int d = 0; d < 4; ++d)
          y[static_cast<std::size_t>(d)] =
              l < 3 ? 2 * x[static_cast<std::size_t>(l)][static_cast<std::size_t>(d)]
                    : x[static_cast<std::size_t>(tri_edges[static_cast<std::size_t>(l - 3)][0])]
                       [static_cast<std::size_t>(d)] +
                          x[static_cast<std::size_t>(tri_edges[static_cast<std::size_t>(l - 3)][1])]
                           [static_cast<std::size_t>(d)];
        const int mask = support_mask(y);
        const Index owner = supports.of(b, mask);
        TableIndex number = kUnknown;
        if (in(refined, owner)) {
          if (l < 3) {
            number = vertex_of[static_cast<std::size_t>(coarse.boundary_facets(f, l))];
          } else {
            number = boundary.find(owner, key_in(base, b, owner, y));
          }
        }
        node[static_cast<std::size_t>(l)] = number;
        complete = number >= 0;
      }
      if (!complete) continue;
      for (int ch = 0; ch < 4; ++ch)
        for (int j = 0; j < 3; ++j)
          fine.boundary_facets(4 * f + ch, j) = node[static_cast<std::size_t>(
              facet_table.child_nodes[static_cast<std::size_t>(ch)][static_cast<std::size_t>(j)])];
    }

    const Index fine_per_block = 8 * per_block;
    fine.present_cells = block_cell_ranges(near_blocks, fine_per_block);
    NestedBlocks nested;
    nested.base_cells = &h.levels[static_cast<std::size_t>(base_level)].cells;
    nested.owner = base_owner;
    nested.cells_per_block = fine_per_block;
    nested.first_vertex = first_vertex;
    blocks.push_back(std::move(nested));
    h.transfers.emplace_back();  // the parent layout only (RefinedMesh::parent_of)
    h.levels.push_back(std::move(fine));

    coarse_first_vertex = std::move(first_vertex);
    new_vertices = std::move(fine_vertices);
    new_edges = std::move(fine_edges);
    new_faces = std::move(fine_faces);
    per_block = fine_per_block;
  }
}

}  // namespace

template <int dim>
void refine_partially(MeshHierarchy<dim>& h, const std::vector<int>& base_owner, int rank, int levels_above,
                      std::vector<NestedBlocks>& blocks, const EdgeNumbering* base_edges) {
  if constexpr (dim == 2) {
    std::optional<EdgeNumbering> own;
    if (!base_edges) base_edges = &own.emplace(h.levels.back());
    refine_triangles(h, *base_edges, base_owner, rank, levels_above, blocks);
  } else {
    refine_tetrahedra(h, base_owner, rank, levels_above, blocks);
  }
}

template void refine_partially(MeshHierarchy<2>&, const std::vector<int>&, int, int,
                               std::vector<NestedBlocks>&, const EdgeNumbering*);
template void refine_partially(MeshHierarchy<3>&, const std::vector<int>&, int, int,
                               std::vector<NestedBlocks>&, const EdgeNumbering*);

}  // namespace warpfem::fem
