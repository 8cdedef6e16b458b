#include "fem/dofs/dof_distribution.hpp"

#include <algorithm>
#include <memory>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>

#include "core/error.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/scatter.hpp"
#include "core/prefault.hpp"
#include "core/threads.hpp"
#include "fem/dofs/cell_partition.hpp"

namespace warpfem::fem {

namespace {
int communicator_size(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  return size;
}
}  // namespace

template <int dim>
DofDistribution<dim>::DofDistribution(MPI_Comm comm, const Mesh<dim>& mesh, const DofMap<dim>& dofs)
    : DofDistribution(comm, mesh, dofs, partition_cells(mesh, communicator_size(comm))) {}

template <int dim>
DofDistribution<dim>::DofDistribution(MPI_Comm comm, const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                      const std::vector<int>& cell_owner)
    : comm_(comm), dofs_(&dofs) {
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &size_);
  mesh.require_whole("DofDistribution from a list of cell owners");
  const auto [lowest, highest] = std::minmax_element(cell_owner.begin(), cell_owner.end());
  check_owners(mesh.num_cells(), static_cast<Index>(cell_owner.size()), cell_owner.empty() ? 0 : *lowest,
               cell_owner.empty() ? 0 : *highest);
  if (size_ == 1) {
    local_cells_.resize(static_cast<std::size_t>(mesh.num_cells()));
    std::iota(local_cells_.begin(), local_cells_.end(), Index{0});
  } else {
    local_cells_.reserve(static_cast<std::size_t>(std::count(cell_owner.begin(), cell_owner.end(), rank_)));
    for (Index c = 0; c < mesh.num_cells(); ++c)
      if (cell_owner[static_cast<std::size_t>(c)] == rank_) local_cells_.push_back(c);
  }
  own_by_cells(mesh, dofs, [&](Index c) { return cell_owner[static_cast<std::size_t>(c)]; });
  number(mesh, dofs);
}

template <int dim>
DofDistribution<dim>::DofDistribution(MPI_Comm comm, const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                      const NestedBlocks& blocks)
    : comm_(comm), dofs_(&dofs) {
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &size_);
  require(blocks.num_cells() == mesh.num_cells(), "DofDistribution: " + std::to_string(blocks.num_blocks()) +
                                                      " blocks of " + std::to_string(blocks.cells_per_block) +
                                                      " cells for a mesh of " +
                                                      std::to_string(mesh.num_cells()) + " cells");
  const auto [lowest, highest] = std::minmax_element(blocks.owner.begin(), blocks.owner.end());
  check_owners(mesh.num_cells(), mesh.num_cells(), blocks.owner.empty() ? 0 : *lowest,
               blocks.owner.empty() ? 0 : *highest);
  const Index nb = blocks.num_blocks(), per_block = blocks.cells_per_block;
  const auto block_owner = [&](Index b) { return blocks.owner[static_cast<std::size_t>(b)]; };
  // The rank's cells: whole blocks.
  const auto mine = [&](Index b) { return size_ == 1 || block_owner(b) == rank_; };
  Index num_local = 0;
  for (Index b = 0; b < nb; ++b) num_local += mine(b) ? per_block : 0;
  resize_prefaulted(local_cells_, static_cast<std::size_t>(num_local));
  for (Index b = 0, i = 0; b < nb; ++b)
    if (mine(b)) {
      std::iota(local_cells_.begin() + i, local_cells_.begin() + i + per_block, b * per_block);
      i += per_block;
    }
  if (size_ > 1 && dofs.dofs_are_vertices()) {
    // P1/Q1: the first cell containing a vertex in [first_vertex[b],
    // first_vertex[b + 1]) is one of block b's, so b's owner owns it. No pass
    // over the cells (on a partial mesh most of them are not stored).
    const std::vector<TableIndex>& first = blocks.first_vertex;
    const Index nd = dofs.num_dofs();
    bool ranges_ok = static_cast<Index>(first.size()) == nb + 1 && first[0] == 0 && first.back() <= nd;
    for (Index b = 0; ranges_ok && b < nb; ++b)
      ranges_ok = first[static_cast<std::size_t>(b)] <= first[static_cast<std::size_t>(b + 1)];
    require(ranges_ok, "DofDistribution: the blocks' vertex ranges do not fit the mesh's " +
                           std::to_string(nd) + " vertices (levels must come from refine_uniformly)");
    resize_prefaulted(owner_, static_cast<std::size_t>(nd));
    for (Index b = 0; b < nb; ++b)
      std::fill(owner_.begin() + first[static_cast<std::size_t>(b)],
                owner_.begin() + first[static_cast<std::size_t>(b + 1)], block_owner(b));
    std::fill(owner_.begin() + first.back(), owner_.end(), size_ - 1);  // vertices in no cell
  } else {
    mesh.require_whole("DofDistribution of a space with DOFs other than vertices");
    own_by_cells(mesh, dofs, [&](Index c) { return blocks.cell_owner(c); });
  }
  number(mesh, dofs);
  // Cells that can hold an owned DOF: those of the blocks next to the rank's.
  if (size_ > 1) candidate_cells_ = block_cell_ranges(blocks.blocks_near(rank_), per_block);
}

template <int dim>
void DofDistribution<dim>::check_owners(Index num_cells, Index num_listed, int lowest, int highest) const {
  require(num_listed == num_cells, "DofDistribution: " + std::to_string(num_listed) + " cell owners for " +
                                       std::to_string(num_cells) + " cells");
  if (num_cells > 0 && (lowest < 0 || highest >= size_))
    throw Error("DofDistribution: cell owner " + std::to_string(lowest < 0 ? lowest : highest) +
                " is not a rank of a communicator of size " + std::to_string(size_));
}

template <int dim>
template <class CellOwner>
void DofDistribution<dim>::own_by_cells(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                        const CellOwner& cell_owner) {
  const Index nd = dofs.num_dofs();
  if (size_ == 1) {  // everything is rank 0's: no pass over the cells
    owner_.assign(static_cast<std::size_t>(nd), 0);
    return;
  }
  // Cells in reverse order, every visit overwriting: the first cell containing
  // a DOF writes last. DOFs in no cell stay the last rank's.
  owner_.assign(static_cast<std::size_t>(nd), size_ - 1);
  const IndexTable& cd = dofs.cell_dofs();
  for (Index c = mesh.num_cells() - 1; c >= 0; --c) {
    const int r = cell_owner(c);
    for (Index k = 0; k < cd.cols(); ++k) owner_[static_cast<std::size_t>(cd(c, k))] = r;
  }
}

template <int dim>
void DofDistribution<dim>::number(const Mesh<dim>& mesh, const DofMap<dim>& dofs) {
  const IndexTable& cd = dofs.cell_dofs();
  const Index nd = dofs.num_dofs();
  std::vector<PetscInt> count(static_cast<std::size_t>(size_) + 1, 0);
  for (Index d = 0; d < nd; ++d) ++count[static_cast<std::size_t>(owner_[static_cast<std::size_t>(d)]) + 1];
  std::partial_sum(count.begin(), count.end(), count.begin());
  owned_begin_ = count[static_cast<std::size_t>(rank_)];
  owned_end_ = count[static_cast<std::size_t>(rank_) + 1];
  num_global_ = count[static_cast<std::size_t>(size_)];
  std::vector<PetscInt> next(count.begin(), count.end() - 1);
  if (dofs.dofs_are_vertices()) {
    // P1/Q1: in vertex order (refine_uniformly numbers vertices by first use).
    global_.resize(static_cast<std::size_t>(nd));
    if (size_ == 1)
      std::iota(global_.begin(), global_.end(), PetscInt{0});
    else
      for (Index d = 0; d < nd; ++d) global_[d] = next[owner_[d]]++;
    return;
  }
  // Higher orders: by first use in the cells (in cell order), so that a cell's
  // DOFs are close in PETSc's numbering (vertex and edge nodes interleaved).
  global_.assign(static_cast<std::size_t>(nd), -1);
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (Index k = 0; k < cd.cols(); ++k)
      if (PetscInt& g = global_[cd(c, k)]; g < 0) g = next[owner_[cd(c, k)]]++;
  for (Index d = 0; d < nd; ++d)
    if (global_[d] < 0) global_[d] = next[owner_[d]]++;
}

template <int dim>
void DofDistribution<dim>::build_relevant() const {
  const IndexTable& cd = dofs_->cell_dofs();
  const Index nd = dofs_->num_dofs();
  relevant_index_.assign(static_cast<std::size_t>(nd), -1);
  Index count = 0;
  for (Index c : local_cells_)
    for (Index k = 0; k < cd.cols(); ++k)
      if (Index& r = relevant_index_[cd(c, k)]; r < 0) r = 0, ++count;
  relevant_.reserve(static_cast<std::size_t>(count));
  for (Index d = 0; d < nd; ++d)
    if (relevant_index_[d] == 0) {
      relevant_index_[d] = static_cast<Index>(relevant_.size());
      relevant_.push_back(d);
    }
}

template <int dim>
petsc::Vector DofDistribution<dim>::create_vector() const {
  petsc::Vector v;
  WARPFEM_PETSC_CHECK(VecCreateMPI(comm_, num_owned(), num_global_, v.out()));
  return v;
}

template <int dim>
VectorX DofDistribution<dim>::gather_relevant(Vec v) const {
  const std::vector<Index>& relevant = relevant_dofs();
  const PetscInt n = static_cast<PetscInt>(relevant.size());
  if (!scatter_) {
    std::vector<PetscInt> from(relevant.size());
    for (std::size_t i = 0; i < relevant.size(); ++i) from[i] = global_[relevant[i]];
    petsc::IndexSet is;
    WARPFEM_PETSC_CHECK(ISCreateGeneral(PETSC_COMM_SELF, n, from.data(), PETSC_COPY_VALUES, is.out()));
    WARPFEM_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, n, relevant_values_.out()));
    WARPFEM_PETSC_CHECK(VecScatterCreate(v, is.get(), relevant_values_.get(), nullptr, scatter_.out()));
  }
  return petsc::scatter_forward(scatter_.get(), v, relevant_values_.get());
}

template <int dim>
VectorX DofDistribution<dim>::gather_all(Vec v) const {
  const std::vector<PetscScalar> a = petsc::gather_to_all(v);
  VectorX out(static_cast<Index>(global_.size()));
  for (std::size_t d = 0; d < global_.size(); ++d) out(static_cast<Index>(d)) = a[global_[d]];
  return out;
}

template <int dim>
void DofDistribution<dim>::preallocation(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                         std::vector<PetscInt>& d_nnz, std::vector<PetscInt>& o_nnz) const {
  std::vector<PetscInt> row_ptr, cols;
  sparsity(mesh, dofs, row_ptr, cols);
  d_nnz.assign(static_cast<std::size_t>(num_owned()), 0);
  o_nnz.assign(static_cast<std::size_t>(num_owned()), 0);
  for (PetscInt r = 0; r < num_owned(); ++r)
    for (PetscInt k = row_ptr[r]; k < row_ptr[r + 1]; ++k)
      ++(cols[k] >= owned_begin_ && cols[k] < owned_end_ ? d_nnz : o_nnz)[static_cast<std::size_t>(r)];
}

template <int dim>
void DofDistribution<dim>::sparsity(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                    std::vector<PetscInt>& row_ptr, std::vector<PetscInt>& cols) const {
  pattern(mesh, dofs, row_ptr, cols, nullptr, nullptr);
}

template <int dim>
void DofDistribution<dim>::sparsity_split(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                          std::vector<PetscInt>& row_ptr, std::vector<PetscInt>& cols,
                                          std::vector<PetscInt>& off_row_ptr,
                                          std::vector<PetscInt>& off_cols) const {
  pattern(mesh, dofs, row_ptr, cols, &off_row_ptr, &off_cols);
}

template <int dim>
void DofDistribution<dim>::pattern(const Mesh<dim>& mesh, const DofMap<dim>& dofs,
                                   std::vector<PetscInt>& row_ptr, std::vector<PetscInt>& cols,
                                   std::vector<PetscInt>* off_row_ptr,
                                   std::vector<PetscInt>* off_cols) const {
  const bool split = off_row_ptr != nullptr;
  const IndexTable& cd = dofs.cell_dofs();
  const Index nc = mesh.num_cells(), nloc = cd.cols();
  const PetscInt rows = num_owned();
  const auto owned_row = [&](Index d) {
    return owner_[d] == rank_ ? global_[d] - owned_begin_ : PetscInt{-1};
  };
  // 1. Every row holds its diagonal, and every cell offers its other nloc - 1
  // global DOFs as candidate columns to each of its owned rows: count the
  // candidates per row. Nested levels name the cell ranges that can hold an
  // owned DOF; otherwise every cell is looked at.
  std::vector<PetscInt> slot(static_cast<std::size_t>(rows) + 1, 1);
  slot[0] = 0;
  const std::vector<std::array<Index, 2>> every_cell{{0, nc}};
  const auto& scanned = candidate_cells_.empty() ? every_cell : candidate_cells_;
  if constexpr (dim == 3) {
    pattern_by_row_cells(dofs, scanned, row_ptr, cols, off_row_ptr, off_cols);
    return;
  }
  for (const auto& [first, last] : scanned)
    for (Index c = first; c < last; ++c)
      for (Index k = 0; k < nloc; ++k)
        if (const PetscInt r = owned_row(cd(c, k)); r >= 0) slot[r + 1] += static_cast<PetscInt>(nloc - 1);
  for (PetscInt r = 0; r < rows; ++r) slot[r + 1] += slot[r];
  // 2. One pass over the same cells in order: the cell table is read
  // sequentially and the rows of a cell lie close together (DOFs are numbered
  // by first use), so the candidates are written to nearby buckets. slot[r]
  // serves as row r's write position: afterwards it is the row's end, and row r
  // starts at slot[r - 1] (no second array of row positions).
  const auto candidates = std::make_unique_for_overwrite<PetscInt[]>(static_cast<std::size_t>(slot[rows]));
  prefault(candidates.get(), static_cast<std::size_t>(slot[rows]) * sizeof(PetscInt));
  for (PetscInt r = 0; r < rows; ++r) candidates[static_cast<std::size_t>(slot[r]++)] = owned_begin_ + r;
  const auto row_begin = [&](PetscInt r) { return candidates.get() + (r > 0 ? slot[r - 1] : 0); };
  // The DOFs per cell as a compile-time constant where it is a common one: the
  // copies of a few indices then inline instead of calling memcpy per row.
  const auto offer = [&]<int NLOC>(std::integral_constant<int, NLOC>) {
    PetscInt global_cell[NLOC];
    for (const auto& [first, last] : scanned)
      for (Index c = first; c < last; ++c) {
        const TableIndex* d = &cd(c, 0);
        for (int k = 0; k < NLOC; ++k) global_cell[k] = global_[d[k]];
        for (int k = 0; k < NLOC; ++k)
          if (const PetscInt r = owned_row(d[k]); r >= 0) {
            PetscInt* out = candidates.get() + slot[r];
            for (int j = 0; j < NLOC; ++j)
              if (j != k) *out++ = global_cell[j];
            slot[r] += NLOC - 1;
          }
      }
  };
  switch (nloc) {
    case 3: offer(std::integral_constant<int, 3>{}); break;
    case 4: offer(std::integral_constant<int, 4>{}); break;
    case 6: offer(std::integral_constant<int, 6>{}); break;
    case 8: offer(std::integral_constant<int, 8>{}); break;
    case 9: offer(std::integral_constant<int, 9>{}); break;
    case 10: offer(std::integral_constant<int, 10>{}); break;
    case 27: offer(std::integral_constant<int, 27>{}); break;
    default: {
      std::vector<PetscInt> global_cell(static_cast<std::size_t>(nloc));
      for (const auto& [first, last] : scanned)
        for (Index c = first; c < last; ++c) {
          for (Index k = 0; k < nloc; ++k) global_cell[k] = global_[cd(c, k)];
          for (Index k = 0; k < nloc; ++k)
            if (const PetscInt r = owned_row(cd(c, k)); r >= 0) {
              PetscInt* out = candidates.get() + slot[r];
              for (Index j = 0; j < nloc; ++j)
                if (j != k) *out++ = global_cell[j];
              slot[r] += static_cast<PetscInt>(nloc - 1);
            }
        }
    }
  }
  // 3. Sort and deduplicate every row's candidates in place (blocks of rows on
  // the threads), then pack the rows. Split: a sorted row's columns of other
  // ranks are a prefix (below the own range) and a suffix (above it).
  const Index blocks = std::max<Index>(1, std::min<Index>(64, rows / 4096));
  row_ptr.assign(static_cast<std::size_t>(rows) + 1, 0);
  if (split) off_row_ptr->assign(static_cast<std::size_t>(rows) + 1, 0);
  parallel_for(blocks, 1, [&](Index first_block, Index last_block) {
    for (Index blk = first_block; blk < last_block; ++blk)
      for (PetscInt r = static_cast<PetscInt>(rows * blk / blocks); r < rows * (blk + 1) / blocks; ++r) {
        PetscInt* begin = row_begin(r);
        PetscInt* end = candidates.get() + slot[r];
        // Insertion into the sorted, duplicate-free prefix (the diagonal first): a
        // row has few distinct columns (7 for P1) among its candidates (13), so
        // this beats sort + unique.
        PetscInt* kept = begin + 1;
        for (PetscInt* it = begin + 1; it != end; ++it) {
          const PetscInt g = *it;
          PetscInt* j = kept;
          while (j > begin && j[-1] > g) --j;
          if (j > begin && j[-1] == g) continue;
          // Shift [j, kept) up by one, g into the gap: a few entries, in registers
          // (a plain copy loop would become a memmove call per insertion).
          for (PetscInt carry = g; j <= kept; ++j) std::swap(carry, *j);
          ++kept;
        }
        PetscInt length = static_cast<PetscInt>(kept - begin);  // a length for now
        if (split && (*begin < owned_begin_ || kept[-1] >= owned_end_)) {
          const PetscInt lo = static_cast<PetscInt>(std::lower_bound(begin, kept, owned_begin_) - begin);
          const PetscInt hi = static_cast<PetscInt>(kept - std::lower_bound(begin, kept, owned_end_));
          (*off_row_ptr)[static_cast<std::size_t>(r) + 1] = lo + hi;
          length -= lo + hi;
        }
        row_ptr[r + 1] = length;
      }
  });
  for (PetscInt r = 0; r < rows; ++r) row_ptr[r + 1] += row_ptr[r];
  resize_prefaulted(cols, static_cast<std::size_t>(row_ptr[rows]));
  if (!split) {
    parallel_for(blocks, 1, [&](Index first_block, Index last_block) {
      for (Index blk = first_block; blk < last_block; ++blk)
        for (PetscInt r = static_cast<PetscInt>(rows * blk / blocks); r < rows * (blk + 1) / blocks; ++r)
          std::copy(row_begin(r), row_begin(r) + (row_ptr[r + 1] - row_ptr[r]), cols.begin() + row_ptr[r]);
    });
    return;
  }
  std::vector<PetscInt>& orp = *off_row_ptr;
  for (PetscInt r = 0; r < rows; ++r) orp[r + 1] += orp[r];
  off_cols->resize(static_cast<std::size_t>(orp[rows]));
  parallel_for(blocks, 1, [&](Index first_block, Index last_block) {
    for (Index blk = first_block; blk < last_block; ++blk)
      for (PetscInt r = static_cast<PetscInt>(rows * blk / blocks); r < rows * (blk + 1) / blocks; ++r) {
        const PetscInt* row = row_begin(r);
        const PetscInt off = orp[r + 1] - orp[r], own = row_ptr[r + 1] - row_ptr[r];
        // The sorted row's columns below the own range come first.
        const PetscInt lo =
            off == 0 ? 0 : static_cast<PetscInt>(std::lower_bound(row, row + own + off, owned_begin_) - row);
        PetscInt* out = cols.data() + row_ptr[r];
        for (PetscInt k = 0; k < own; ++k) out[k] = row[lo + k] - owned_begin_;
        PetscInt* out_off = off_cols->data() + orp[r];
        std::copy(row, row + lo, out_off);
        std::copy(row + lo + own, row + lo + own + (off - lo), out_off + lo);
      }
  });
}

template <int dim>
void DofDistribution<dim>::pattern_by_row_cells(const DofMap<dim>& dofs,
                                                const std::vector<std::array<Index, 2>>& scanned,
                                                std::vector<PetscInt>& row_ptr, std::vector<PetscInt>& cols,
                                                std::vector<PetscInt>* off_row_ptr,
                                                std::vector<PetscInt>* off_cols) const {
  const bool split = off_row_ptr != nullptr;
  const IndexTable& cd = dofs.cell_dofs();
  const int nloc = static_cast<int>(cd.cols());
  const PetscInt rows = num_owned();
  const auto owned_row = [&](Index d) {
    return owner_[d] == rank_ ? global_[d] - owned_begin_ : PetscInt{-1};
  };
  // 1. The cells of every owned row (compressed rows of cell indices).
  std::vector<PetscInt> cell_start(static_cast<std::size_t>(rows) + 1, 0);
  for (const auto& [first, last] : scanned)
    for (Index c = first; c < last; ++c)
      for (int k = 0; k < nloc; ++k)
        if (const PetscInt r = owned_row(cd(c, k)); r >= 0) ++cell_start[static_cast<std::size_t>(r) + 1];
  for (PetscInt r = 0; r < rows; ++r) cell_start[r + 1] += cell_start[r];
  std::vector<TableIndex> row_cells;
  resize_prefaulted(row_cells, static_cast<std::size_t>(cell_start[rows]));
  {
    std::vector<PetscInt> next(cell_start.begin(), cell_start.end() - 1);
    for (const auto& [first, last] : scanned)
      for (Index c = first; c < last; ++c)
        for (int k = 0; k < nloc; ++k)
          if (const PetscInt r = owned_row(cd(c, k)); r >= 0)
            row_cells[next[r]++] = static_cast<TableIndex>(c);
  }
  // 2. Every row merges its cells' DOFs twice, duplicates dropped by a mark
  // per column (the row that last took it): once to count its columns (own
  // and other ranks'), once to write them; then sorted. Blocks of rows on
  // the threads, one set of marks each.
  const Index blocks = std::max<Index>(1, std::min<Index>(thread_count(), rows / 4096));
  const auto row_range = [&](Index blk) {
    return std::array<PetscInt, 2>{static_cast<PetscInt>(rows * blk / blocks),
                                   static_cast<PetscInt>(rows * (blk + 1) / blocks)};
  };
  // Calls take(global column) for each distinct column of row r, its diagonal
  // first. Marks are per mesh DOF, so a rank needs them only for the DOFs its
  // mesh stores.
  const auto merge_row = [&](PetscInt r, std::vector<PetscInt>& mark, auto&& take) {
    const PetscInt diagonal = owned_begin_ + r;
    take(diagonal);
    for (PetscInt m = cell_start[r]; m < cell_start[r + 1]; ++m) {
      const TableIndex* d = &cd(row_cells[static_cast<std::size_t>(m)], 0);
      for (int j = 0; j < nloc; ++j)
        if (mark[static_cast<std::size_t>(d[j])] != r) {
          mark[static_cast<std::size_t>(d[j])] = r;
          if (const PetscInt g = global_[d[j]]; g != diagonal) take(g);
        }
    }
  };
  const auto own = [&](PetscInt g) { return g >= owned_begin_ && g < owned_end_; };
  row_ptr.assign(static_cast<std::size_t>(rows) + 1, 0);
  if (split) off_row_ptr->assign(static_cast<std::size_t>(rows) + 1, 0);
  parallel_for(blocks, 1, [&](Index first_block, Index last_block) {
    std::vector<PetscInt> mark(global_.size(), -1);
    for (Index blk = first_block; blk < last_block; ++blk)
      for (auto [r, end] = row_range(blk); r < end; ++r) {
        PetscInt in = 0, off = 0;
        merge_row(r, mark, [&](PetscInt g) { ++(!split || own(g) ? in : off); });
        row_ptr[static_cast<std::size_t>(r) + 1] = in;
        if (split) (*off_row_ptr)[static_cast<std::size_t>(r) + 1] = off;
      }
  });
  for (PetscInt r = 0; r < rows; ++r) row_ptr[r + 1] += row_ptr[r];
  resize_prefaulted(cols, static_cast<std::size_t>(row_ptr[rows]));
  if (split) {
    std::vector<PetscInt>& orp = *off_row_ptr;
    for (PetscInt r = 0; r < rows; ++r) orp[r + 1] += orp[r];
    off_cols->resize(static_cast<std::size_t>(orp[rows]));
  }
  parallel_for(blocks, 1, [&](Index first_block, Index last_block) {
    std::vector<PetscInt> mark(global_.size(), -1);
    for (Index blk = first_block; blk < last_block; ++blk)
      for (auto [r, end] = row_range(blk); r < end; ++r) {
        PetscInt* const in_begin = cols.data() + row_ptr[r];
        PetscInt* in = in_begin;
        PetscInt* const off_begin = split ? off_cols->data() + (*off_row_ptr)[r] : nullptr;
        PetscInt* off = off_begin;
        // Own columns local when split, global otherwise; other ranks' global.
        merge_row(r, mark, [&](PetscInt g) {
          if (!split)
            *in++ = g;
          else if (own(g))
            *in++ = g - owned_begin_;
          else
            *off++ = g;
        });
        std::sort(in_begin, in);
        if (split) std::sort(off_begin, off);
      }
  });
}

template class DofDistribution<2>;
template class DofDistribution<3>;

}  // namespace warpfem::fem
