#include "fem/dofs/cell_partition.hpp"

#include <algorithm>
#include <numeric>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/mesh/uniform_refinement.hpp"

namespace warpfem::fem {
namespace {
std::uint64_t spread_bits(std::uint32_t v) {
  std::uint64_t x = v;
  x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
  x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
  x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
  x = (x | (x << 2)) & 0x3333333333333333ull;
  x = (x | (x << 1)) & 0x5555555555555555ull;
  return x;
}
/// The low 21 bits of v, two zero bits after each (3D Morton codes).
std::uint64_t spread_bits_3(std::uint32_t v) {
  std::uint64_t x = v & 0x1FFFFFu;
  x = (x | (x << 32)) & 0x001F00000000FFFFull;
  x = (x | (x << 16)) & 0x001F0000FF0000FFull;
  x = (x | (x << 8)) & 0x100F00F00F00F00Full;
  x = (x | (x << 4)) & 0x10C30C30C30C30C3ull;
  x = (x | (x << 2)) & 0x1249249249249249ull;
  return x;
}
}  // namespace

template <int dim>
std::vector<int> partition_cells(const Mesh<dim>& mesh, int num_parts) {
  mesh.require_whole("partition_cells");
  const Index nc = mesh.num_cells();
  std::vector<int> owner(static_cast<std::size_t>(nc), 0);
  if (num_parts <= 1 || nc == 0) return owner;
  const int nv = vertices_per_cell(mesh.cell_type);
  // Morton code of each cell's centroid in the vertices' bounding box (every rank
  // computes the same codes), written straight into the (code, cell) keys.
  const Point<dim> lo = mesh.vertices.colwise().minCoeff().transpose();
  const Point<dim> hi = mesh.vertices.colwise().maxCoeff().transpose();
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<std::pair<std::uint64_t, Index>> key(static_cast<std::size_t>(nc));
  for (Index c = 0; c < nc; ++c) {
    double x[dim] = {};
    for (int k = 0; k < nv; ++k) {
      const Index v = mesh.cells(c, k);
      for (int d = 0; d < dim; ++d) x[d] += mesh.vertices(v, d);
    }
    const auto q = [&](double t, int d) {
      return static_cast<std::uint32_t>(std::clamp((t / nv - lo(d)) / extent, 0.0, 1.0) * 4294967295.0);
    };
    std::uint64_t code = 0;
    if constexpr (dim == 2)
      code = spread_bits(q(x[0], 0)) | (spread_bits(q(x[1], 1)) << 1);
    else  // 21 bits per axis: the top bits of the 32-bit quantization
      code = spread_bits_3(q(x[0], 0) >> 11) | (spread_bits_3(q(x[1], 1) >> 11) << 1) |
             (spread_bits_3(q(x[2], 2) >> 11) << 2);
    key[static_cast<std::size_t>(c)] = {code, c};
  }
  // Part p gets the cells at positions [p nc / P, (p + 1) nc / P) of the curve order
  // (ties broken by cell index). Only the P − 1 split positions matter, so select
  // them (nth_element, O(nc) each) instead of sorting all cells.
  const auto split = [&](int p) {
    return key.begin() + static_cast<std::ptrdiff_t>((Index{p} * nc) / num_parts);
  };
  if (num_parts <= 16) {
    for (int p = 1; p < num_parts; ++p) std::nth_element(split(p - 1), split(p), key.end());
  } else {
    std::sort(key.begin(), key.end());
  }
  for (int p = 0; p < num_parts; ++p)
    for (auto it = split(p); it != split(p + 1); ++it) owner[static_cast<std::size_t>(it->second)] = p;
  return owner;
}

template std::vector<int> partition_cells(const Mesh<2>&, int);
template std::vector<int> partition_cells(const Mesh<3>&, int);

std::vector<int> inherit_partition(const std::vector<int>& coarse_owner, Index children_per_cell) {
  require(children_per_cell > 0, "inherit_partition: no children per cell");
  std::vector<int> owner(coarse_owner.size() * static_cast<std::size_t>(children_per_cell));
  for (std::size_t c = 0; c < owner.size(); ++c)
    owner[c] = coarse_owner[c / static_cast<std::size_t>(children_per_cell)];
  return owner;
}

}  // namespace warpfem::fem
