#include "core/mesh/mesh.hpp"

#include <limits>

#include "core/error.hpp"

namespace warpfem {

TableIndex checked_table_size(Index count, const std::string& what) {
  if (count < 0 || count > std::numeric_limits<TableIndex>::max())
    throw Error(
        what + ": " + std::to_string(count) + " entries do not fit the 32-bit mesh tables (at most " +
            std::to_string(std::numeric_limits<TableIndex>::max()) + ")",
        {.file = "",
         .key_path = "",
         .hint = "use fewer refinements or a coarser mesh (every rank holds the whole mesh hierarchy)"});
  return static_cast<TableIndex>(count);
}

template <int dim>
std::vector<std::array<Index, 2>> Mesh<dim>::cell_ranges() const {
  if (partial) return present_cells;
  return {{0, num_cells()}};
}

template <int dim>
void Mesh<dim>::require_whole(const std::string& what) const {
  if (partial)
    throw Error(what + " needs the whole mesh, but this level was refined only around one rank's cells",
                {.file = "",
                 .key_path = "",
                 .hint = "build the MeshHierarchy without a partition (every level whole on every rank)"});
}

template <int dim>
Real Mesh<dim>::max_edge_length() const {
  Real h = 0;
  for (const auto& [first, last] : cell_ranges())
    for (Index c = first; c < last; ++c)
      for (const auto& e : cell_edges(cell_type))
        h = std::max(h, (vertex(cells(c, e[0])) - vertex(cells(c, e[1]))).norm());
  return h;
}

template struct Mesh<2>;
template struct Mesh<3>;

}  // namespace warpfem
