// The values seam: CellValues' physical gradients obey the chain rule with a
// Jacobian computed independently from the map and the simple cell, and the
// facet geometry closes up with the cell geometry (perimeter, ∮ n ds = 0,
// ∮ x·n ds = 2 |Ω1|).

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <memory>
#include <tuple>

#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/quadrature.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "fem/assembly/integrate.hpp"
#include "mapping/make_map.hpp"

using namespace warpfem;

namespace {

const Polygon& pentagon() {
  static const Polygon p = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}}, "pentagon");
  return p;
}
const Polygon& bent_pentagon() {
  static const Polygon p =
      Polygon::checked({{0, 0}, {1, 0}, {1.2, 1.1}, {0.5, 0.7}, {-0.1, 1}}, "bent pentagon");
  return p;
}

mapping::MapPtr<2> composite() {
  mapping::MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = pentagon();
  spec.target = bent_pentagon();
  return mapping::make_map(spec);
}

std::vector<Index> all_cells(const warpfem::Mesh<2>& mesh) {
  std::vector<Index> cells(static_cast<std::size_t>(mesh.num_cells()));
  for (Index c = 0; c < mesh.num_cells(); ++c) cells[static_cast<std::size_t>(c)] = c;
  return cells;
}

std::vector<Index> all_facets(const warpfem::Mesh<2>& mesh) {
  std::vector<Index> facets(static_cast<std::size_t>(mesh.num_boundary_facets()));
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f) facets[static_cast<std::size_t>(f)] = f;
  return facets;
}

warpfem::Mesh<2> mesh_of(const Polygon& polygon, warpfem::CellType type) {
  warpfem::PolygonMeshOptions options;
  options.max_edge_length = 0.2;
  warpfem::Mesh<2> triangles = warpfem::mesh_polygon(polygon, options);
  return type == warpfem::CellType::triangle ? triangles : warpfem::split_into_quadrilaterals(triangles);
}

class ValuesSeam : public ::testing::TestWithParam<std::tuple<warpfem::CellType, int>> {};

}  // namespace

TEST_P(ValuesSeam, GradientsFollowTheChainRuleWithAnIndependentJacobian) {
  const auto [type, order] = GetParam();
  const warpfem::Mesh<2> mesh = mesh_of(pentagon(), type);
  const auto map = composite();
  const fem::LagrangeElement<2> element(type, order);
  const fem::WarpedGeometry<2> geometry(mesh, all_cells(mesh), warpfem::cell_quadrature<2>(type, 4), *map);
  fem::CellValues<2> values(
      element, geometry, fem::CellValues<2>::update_gradients | fem::CellValues<2>::update_reference_points);
  const fem::LagrangeElement<2> linear(type, 1);
  const auto dG = linear.gradients(geometry.rule().points);
  const auto dphi = element.gradients(geometry.rule().points);
  double worst = 0, worst_point = 0;
  Index visited = 0;
  fem::integrate_cells(geometry, values, fem::point_kernel([&](const fem::CellValues<2>& v, Index q) {
                         // J = J_f(x0) J_G from the map and the cell's vertices, not from the geometry's
                         // arrays.
                         Points<2> x0 = v.reference_point(q).transpose(), x;
                         Jacobians<2> Jf;
                         map->eval_with_jacobian(x0, x, Jf);
                         Matrix<2> JG = Matrix<2>::Zero();
                         for (int k = 0; k < linear.num_dofs(); ++k)
                           for (int d = 0; d < 2; ++d)
                             JG.col(d) += dG[d](q, k) * mesh.vertex(mesh.cells(v.cell(), k));
                         const Matrix<2> J = jacobian_at<2>(Jf, 0) * JG;
                         for (int k = 0; k < v.num_dofs(); ++k) {
                           // Chain rule: J^T ∇φ = ∇̂φ.
                           const Point<2> reference(dphi[0](q, k), dphi[1](q, k));
                           worst =
                               std::max(worst, (J.transpose() * v.shape_gradient(q, k) - reference).norm());
                         }
                         worst_point = std::max(worst_point, (v.point(q) - x.row(0).transpose()).norm());
                         EXPECT_NEAR(v.JxW(q), geometry.rule().weights(q) * J.determinant(), 1e-12);
                         ++visited;
                       }));
  EXPECT_EQ(visited, geometry.num_cells() * geometry.points_per_cell());
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_point, 1e-14);
}

TEST_P(ValuesSeam, FacetGeometryClosesUpWithTheCellGeometry) {
  const auto [type, order] = GetParam();
  const warpfem::Mesh<2> mesh = mesh_of(pentagon(), type);
  const auto map = composite();
  const fem::WarpedGeometry<2> cells(mesh, all_cells(mesh), warpfem::cell_quadrature<2>(type, 6), *map);
  const fem::WarpedFacets<2> facets(mesh, all_facets(mesh), warpfem::gauss_legendre(4), *map);
  const fem::LagrangeElement<2> element(type, order);
  fem::FacetValues<2> values(element, facets);
  double length = 0, flux = 0;
  Point<2> normal_sum = Point<2>::Zero();
  fem::integrate_facets(facets, values, fem::point_kernel([&](const fem::FacetValues<2>& v, Index q) {
                          length += v.JxW(q);
                          normal_sum += v.JxW(q) * v.normal(q);
                          flux += v.JxW(q) * v.point(q).dot(v.normal(q));
                        }));
  // A mean value map is linear on every polygon edge: the boundary of f(Ω0) is the target polygon.
  const double area = fem::integrate(cells, [](const Point<2>&) { return 1.0; });
  EXPECT_NEAR(length, bent_pentagon().perimeter(), 1e-12);
  EXPECT_NEAR(area, bent_pentagon().signed_area(), 1e-5);  // f is not polynomial: a quadrature error
  EXPECT_LT(normal_sum.norm(), 1e-12);
  EXPECT_NEAR(flux, 2 * bent_pentagon().signed_area(), 1e-12);  // divergence theorem, ∇·x = 2
}

TEST_P(ValuesSeam, FacetShapeValuesAreTheTraceOfTheCellElement) {
  // Not a structured binding: the lambda below captures `order` (Clang before 16 cannot capture bindings).
  const warpfem::CellType type = std::get<0>(GetParam());
  const int order = std::get<1>(GetParam());
  const warpfem::Mesh<2> mesh = mesh_of(pentagon(), type);
  const auto map = std::make_shared<mapping::IdentityMap<2>>();
  const fem::WarpedFacets<2> facets(mesh, all_facets(mesh), warpfem::gauss_legendre(3), *map);
  const fem::LagrangeElement<2> element(type, order);
  fem::FacetValues<2> values(element, facets);
  ASSERT_EQ(values.num_dofs(), order + 1);
  // Partition of unity, and the facet's vertex functions interpolate its end points.
  double worst = 0;
  fem::integrate_facets(facets, values, fem::point_kernel([&](const fem::FacetValues<2>& v, Index q) {
                          double sum = 0;
                          Point<2> x = Point<2>::Zero();
                          for (int k = 0; k < v.num_dofs(); ++k) sum += v.shape_value(q, k);
                          for (int k = 0; k < 2; ++k)
                            x += v.shape_value(q, k) * mesh.vertex(mesh.boundary_facets(v.facet(), k));
                          if (order == 2)  // the midpoint node carries the rest of the linear function
                            x += v.shape_value(q, 2) * 0.5 *
                                 (mesh.vertex(mesh.boundary_facets(v.facet(), 0)) +
                                  mesh.vertex(mesh.boundary_facets(v.facet(), 1)));
                          worst = std::max({worst, std::abs(sum - 1), (x - v.point(q)).norm()});
                        }));
  EXPECT_LT(worst, 1e-14);
}

class AffineValues : public ::testing::TestWithParam<int> {};

TEST_P(AffineValues, InterpolantOfALinearFunctionHasItsGradient) {
  const warpfem::CellType type = warpfem::CellType::triangle;  // affine cells: exact gradients
  const int order = GetParam();
  const warpfem::Mesh<2> mesh = mesh_of(pentagon(), type);
  const auto map = std::make_shared<mapping::IdentityMap<2>>();
  const fem::LagrangeElement<2> element(type, order);
  const fem::WarpedGeometry<2> geometry(mesh, all_cells(mesh), warpfem::cell_quadrature<2>(type, 2), *map);
  fem::CellValues<2> values(element, geometry, fem::CellValues<2>::update_gradients);
  const Point<2> a(0.3, -1.7);
  std::vector<double> u(static_cast<std::size_t>(element.num_dofs()));
  const fem::LagrangeElement<2> linear(type, 1);
  const MatrixX G = linear.values(element.nodes());
  double worst = 0;
  fem::integrate_cells(geometry, values,
                       fem::make_kernel(
                           [&](const fem::CellValues<2>& v) {
                             for (int k = 0; k < v.num_dofs(); ++k) {
                               Point<2> node = Point<2>::Zero();
                               for (int j = 0; j < linear.num_dofs(); ++j)
                                 node += G(k, j) * mesh.vertex(mesh.cells(v.cell(), j));
                               u[static_cast<std::size_t>(k)] = a.dot(node) + 2.0;
                             }
                             return true;
                           },
                           [&](const fem::CellValues<2>& v, Index q) {
                             worst = std::max(worst, (v.gradient(q, u.data()) - a).norm());
                             worst =
                                 std::max(worst, std::abs(v.value(q, u.data()) - a.dot(v.point(q)) - 2.0));
                           },
                           [](const fem::CellValues<2>&) {}));
  EXPECT_LT(worst, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Orders, AffineValues, ::testing::Values(1, 2));
INSTANTIATE_TEST_SUITE_P(Elements, ValuesSeam,
                         ::testing::Combine(::testing::Values(warpfem::CellType::triangle,
                                                              warpfem::CellType::quadrilateral),
                                            ::testing::Values(1, 2)));
