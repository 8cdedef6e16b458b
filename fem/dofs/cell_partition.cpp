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
}  // namespace

std::vector<int> partition_cells(const Mesh<2>& mesh, int num_parts) {
  mesh.require_whole("partition_cells");
  const Index nc = mesh.num_cells();
  std::vector<int> owner(static_cast<std::size_t>(nc), 0);
  if (num_parts <= 1 || nc == 0) return owner;
  const int nv = vertices_per_cell(mesh.cell_type);
  // Morton code of each cell's centroid in the vertices' bounding box (every rank
  // computes the same codes), written straight into the (code, cell) keys.
  const Point<2> lo = mesh.vertices.colwise().minCoeff().transpose();
  const Point<2> hi = mesh.vertices.colwise().maxCoeff().transpose();
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<std::pair<std::uint64_t, Index>> key(static_cast<std::size_t>(nc));
  for (Index c = 0; c < nc; ++c) {
    double x = 0, y = 0;
    for (int k = 0; k < nv; ++k) {
      const Index v = mesh.cells(c, k);
      x += mesh.vertices(v, 0), y += mesh.vertices(v, 1);
    }
    const auto q = [&](double t, int d) {
      return static_cast<std::uint32_t>(std::clamp((t / nv - lo(d)) / extent, 0.0, 1.0) * 4294967295.0);
    };
    key[static_cast<std::size_t>(c)] = {spread_bits(q(x, 0)) | (spread_bits(q(y, 1)) << 1), c};
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

std::vector<int> inherit_partition(const std::vector<int>& coarse_owner) {
  std::vector<int> owner(coarse_owner.size() * RefinedMesh<2>::children_per_cell);
  for (std::size_t c = 0; c < owner.size(); ++c)
    owner[c] = coarse_owner[static_cast<std::size_t>(RefinedMesh<2>::parent_of(static_cast<Index>(c)))];
  return owner;
}

}  // namespace warpfem::fem
