#include "core/mesh/simplex_neighbours.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include "core/error.hpp"

namespace warpfem {

template <int dim>
IndexTable simplex_neighbours(const Mesh<dim>& mesh) {
  mesh.require_whole("simplex_neighbours");
  require(
      mesh.cell_type == (dim == 2 ? CellType::triangle : CellType::tetrahedron),
      "simplex_neighbours: the mesh must consist of " + std::string(dim == 2 ? "triangles" : "tetrahedra"));
  constexpr int corners = dim + 1;
  const Index nc = mesh.num_cells();
  // Every (facet, owner) once, the facet as its sorted vertices; equal facets end up adjacent.
  struct Side {
    std::array<TableIndex, dim> facet;
    Index owner;  // cell * corners + opposite local vertex
  };
  std::vector<Side> sides;
  sides.reserve(static_cast<std::size_t>(nc * corners));
  for (Index c = 0; c < nc; ++c)
    for (int i = 0; i < corners; ++i) {
      Side s{{}, c * corners + i};
      for (int k = 1; k < corners; ++k)
        s.facet[static_cast<std::size_t>(k - 1)] = mesh.cells(c, (i + k) % corners);
      std::sort(s.facet.begin(), s.facet.end());
      sides.push_back(s);
    }
  std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) { return a.facet < b.facet; });
  IndexTable neighbours = IndexTable::Constant(nc, corners, -1);
  for (std::size_t k = 0; k + 1 < sides.size(); ++k)
    if (sides[k].facet == sides[k + 1].facet) {
      const Index a = sides[k].owner, b = sides[k + 1].owner;
      neighbours(a / corners, a % corners) = static_cast<TableIndex>(b / corners);
      neighbours(b / corners, b % corners) = static_cast<TableIndex>(a / corners);
      ++k;
    }
  return neighbours;
}

template IndexTable simplex_neighbours<2>(const Mesh<2>&);
template IndexTable simplex_neighbours<3>(const Mesh<3>&);

}  // namespace warpfem
