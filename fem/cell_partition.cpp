#include "fem/cell_partition.hpp"

#include <algorithm>
#include <numeric>

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
  const Index nc = mesh.num_cells();
  std::vector<int> owner(static_cast<std::size_t>(nc), 0);
  if (num_parts <= 1 || nc == 0) return owner;
  const int nv = vertices_per_cell(mesh.cell_type);
  Points<2> centroid(nc, 2);
  for (Index c = 0; c < nc; ++c) {
    Point<2> s = Point<2>::Zero();
    for (int k = 0; k < nv; ++k) s += mesh.vertex(mesh.cells(c, k));
    centroid.row(c) = (s / nv).transpose();
  }
  const Point<2> lo = centroid.colwise().minCoeff().transpose();
  const Point<2> hi = centroid.colwise().maxCoeff().transpose();
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<std::uint64_t> code(static_cast<std::size_t>(nc));
  for (Index c = 0; c < nc; ++c) {
    const auto q = [&](int d) {
      return static_cast<std::uint32_t>(std::clamp((centroid(c, d) - lo(d)) / extent, 0.0, 1.0) *
                                        4294967295.0);
    };
    code[c] = spread_bits(q(0)) | (spread_bits(q(1)) << 1);
  }
  std::vector<Index> order(static_cast<std::size_t>(nc));
  std::iota(order.begin(), order.end(), Index{0});
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return code[a] < code[b]; });
  for (Index k = 0; k < nc; ++k) owner[order[k]] = static_cast<int>((k * num_parts) / nc);
  return owner;
}

}  // namespace warpfem::fem
