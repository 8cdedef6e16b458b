#include "mapping/harmonic/p1_laplace.hpp"

#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "mapping/harmonic/p1_dirichlet.hpp"

namespace warpfem::mapping {

Mesh<2> auxiliary_mesh(const Polygon& domain, Real max_edge_length, Index max_triangles) {
  require(max_edge_length > 0, "harmonic map: the mesh edge length must be positive");
  const Real area = domain.signed_area();
  const Real estimate = 4 * area / (0.43 * max_edge_length * max_edge_length);
  if (estimate > static_cast<Real>(max_triangles))
    throw Error("harmonic map: a mesh of " + domain.name() + " with edges ≤ " +
                    std::to_string(max_edge_length) + " would have about " +
                    std::to_string(static_cast<long long>(estimate)) + " triangles",
                {.file = "", .key_path = "map.fem_max_edge_length", .hint = "choose a larger edge length"});
  return mesh_polygon(domain,
                      {.max_edge_length = max_edge_length, .max_boundary_edge_length = max_edge_length});
}

MatrixX p1_harmonic_coordinates(const Mesh<2>& mesh, const Polygon& domain,
                                const std::vector<EdgeSpeed>& speeds, Index n) {
  const Index nv = mesh.num_vertices();
  const std::vector<std::optional<BoundaryPoint>> at = boundary_points(mesh, domain);
  MatrixX lambda = MatrixX::Zero(nv, n);
  std::vector<bool> fixed(static_cast<std::size_t>(nv), false);
  std::vector<Real> w(static_cast<std::size_t>(n));
  for (Index v = 0; v < nv; ++v)
    if (at[static_cast<std::size_t>(v)]) {
      fixed[static_cast<std::size_t>(v)] = true;
      boundary_weights(speeds, *at[static_cast<std::size_t>(v)], w.data(), n);
      for (Index k = 0; k < n; ++k) lambda(v, k) = w[static_cast<std::size_t>(k)];
    }
  p1_harmonic_extension(mesh, fixed, lambda);
  return lambda;
}

}  // namespace warpfem::mapping
