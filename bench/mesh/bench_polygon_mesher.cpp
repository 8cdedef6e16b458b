// Meshing a polygon with many vertices: a star-shaped wavy outline with n
// vertices (n from the command line), validated and meshed by CGAL's
// constrained Delaunay refinement with the shape criterion only, as the map
// pipeline meshes a detailed target. Prints the time of validation and
// meshing for each n.
//
//   bench_polygon_mesher [n ...]        (default: 1000 10000 100000)

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "core/mesh/polygon_mesher.hpp"
#include "core/polygon.hpp"
#include "core/timer.hpp"

namespace {

warpfem::Polygon wavy_outline(long n) {
  std::vector<warpfem::Point<2>> v;
  v.reserve(static_cast<std::size_t>(n));
  for (long i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    const double r = 1 + 0.1 * std::sin(12 * t);
    v.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  return warpfem::Polygon(std::move(v), "wavy outline");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long> sizes;
  for (int i = 1; i < argc; ++i) sizes.push_back(std::atol(argv[i]));
  if (sizes.empty()) sizes = {1000, 10000, 100000};
  std::printf("%10s %12s %12s %12s\n", "vertices", "validate s", "mesh s", "triangles");
  for (const long n : sizes) {
    if (n < 3) {
      std::fprintf(stderr, "bench_polygon_mesher: a polygon needs at least 3 vertices, got %ld\n", n);
      return 2;
    }
    warpfem::Stopwatch watch;
    const warpfem::Polygon polygon = wavy_outline(n);
    const double validate = watch.seconds();
    watch.reset();
    const warpfem::Mesh<2> mesh = warpfem::mesh_polygon(polygon);
    std::printf("%10ld %12.3f %12.3f %12ld\n", n, validate, watch.seconds(),
                static_cast<long>(mesh.num_cells()));
  }
  return 0;
}
