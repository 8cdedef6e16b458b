#include "fem/hierarchy/partial_refinement.hpp"

#include <algorithm>
#include <array>
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
#include "fem/hierarchy/refine_by_position.hpp"

namespace warpfem::fem {

namespace {

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

  // 2. The blocks this rank refines (nested_blocks.hpp).
  const RefinedRing ring = refined_ring(base.cells, base_owner, rank);
  const std::vector<char>& near = ring.near;
  const std::vector<char>& refined = ring.refined;
  const std::vector<std::array<Index, 2>>& refined_runs = ring.refined_runs;
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
    std::vector<TableIndex> first_vertex = block_offsets(fine_vertices, where + " vertices");
    std::vector<TableIndex> first_edge = block_offsets(fine_edges, where + " edges");
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

    const Index fine_per_block = 4 * per_block;
    append_partial_level(h, base_level, std::move(fine), ring, base_owner, fine_per_block, first_vertex,
                         blocks);

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

}  // namespace

template <int dim>
void refine_partially(MeshHierarchy<dim>& h, const std::vector<int>& base_owner, int rank, int levels_above,
                      std::vector<NestedBlocks>& blocks, const EdgeNumbering* base_edges) {
  if constexpr (dim == 2) {
    if (h.levels.back().cell_type == CellType::triangle) {
      std::optional<EdgeNumbering> own;
      if (!base_edges) base_edges = &own.emplace(h.levels.back());
      refine_triangles(h, *base_edges, base_owner, rank, levels_above, blocks);
      return;
    }
  }
  refine_by_position(h, base_owner, rank, levels_above, blocks);
}

template void refine_partially(MeshHierarchy<2>&, const std::vector<int>&, int, int,
                               std::vector<NestedBlocks>&, const EdgeNumbering*);
template void refine_partially(MeshHierarchy<3>&, const std::vector<int>&, int, int,
                               std::vector<NestedBlocks>&, const EdgeNumbering*);

}  // namespace warpfem::fem
