// Reference cells, Lagrange elements and quadrature in 2D and 3D: nodal and
// polynomial-reproduction properties, VTK node order, facet traces, and the
// exactness degree of the quadrature rules (exact up to it, not beyond).

#include <gtest/gtest.h>
#include <vtkLagrangeHexahedron.h>
#include <vtkLagrangeQuadrilateral.h>
#include <vtkLagrangeTetra.h>
#include <vtkLagrangeTriangle.h>
#include <vtkNew.h>
#include <vtkPoints.h>

#include <Eigen/Geometry>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/mesh/quadrature.hpp"
#include "fem/reference/lagrange_element.hpp"

using namespace warpfem;
using namespace warpfem::fem;

namespace {

struct ElementCase {
  CellType type;
  int order;
};
std::string case_name(const ::testing::TestParamInfo<ElementCase>& info) {
  return to_string(info.param.type) + "_" + std::to_string(info.param.order);
}

// Interior points well inside the cell: a degree-4 rule's points.
template <int dim>
Points<dim> interior_points(CellType type) {
  return cell_quadrature<dim>(type, 4).points;
}

// Parametric coordinates of VTK's own Lagrange cell with n points, in VTK's order.
MatrixX vtk_parametric_coords(CellType type, int n) {
  double* p = nullptr;
  vtkNew<vtkLagrangeTriangle> tri;
  vtkNew<vtkLagrangeQuadrilateral> quad;
  vtkNew<vtkLagrangeTetra> tet;
  vtkNew<vtkLagrangeHexahedron> hex;
  vtkCell* cell = nullptr;
  switch (type) {
    case CellType::triangle: cell = tri; break;
    case CellType::quadrilateral: cell = quad; break;
    case CellType::tetrahedron: cell = tet; break;
    case CellType::hexahedron: cell = hex; break;
  }
  cell->GetPointIds()->SetNumberOfIds(n);
  cell->GetPoints()->SetNumberOfPoints(n);
  // Simplices derive their order from the point count in Initialize().
  if (type == CellType::triangle) tri->Initialize();
  if (type == CellType::tetrahedron) tet->Initialize();
  if (type == CellType::quadrilateral) quad->SetUniformOrderFromNumPoints(n);
  if (type == CellType::hexahedron) hex->SetUniformOrderFromNumPoints(n);
  p = cell->GetParametricCoords();
  MatrixX out(n, 3);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d) out(k, d) = p[3 * k + d];
  return out;
}

template <int dim>
void check_element(CellType type, int order) {
  const LagrangeElement<dim> el(type, order);
  const Points<dim>& nodes = el.nodes();
  const int n = el.num_dofs();

  // Lagrange property: phi_k(node_j) = delta_kj.
  EXPECT_TRUE(el.values(nodes).isApprox(MatrixX::Identity(n, n), 1e-14));

  // Same node order as VTK's Lagrange cell.
  const MatrixX vtk = vtk_parametric_coords(type, n);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < dim; ++d) EXPECT_EQ(nodes(k, d), vtk(k, d)) << "node " << k << " coordinate " << d;

  const Points<dim> xi = interior_points<dim>(type);
  const MatrixX phi = el.values(xi);
  const auto grad = el.gradients(xi);
  for (Index q = 0; q < xi.rows(); ++q) {
    // Partition of unity (and its derivative).
    EXPECT_NEAR(phi.row(q).sum(), 1.0, 1e-14);
    for (int d = 0; d < dim; ++d) EXPECT_NEAR(grad[d].row(q).sum(), 0.0, 1e-13);
    // Linear precision: sum_k x_k phi_k = x, with gradient the identity.
    for (int e = 0; e < dim; ++e) {
      EXPECT_NEAR(phi.row(q).dot(nodes.col(e)), xi(q, e), 1e-14);
      for (int d = 0; d < dim; ++d) EXPECT_NEAR(grad[d].row(q).dot(nodes.col(e)), d == e ? 1.0 : 0.0, 1e-13);
    }
    // Quadratic precision for order 2: every x_d x_e is interpolated exactly.
    if (order == 2) {
      for (int d = 0; d < dim; ++d)
        for (int e = d; e < dim; ++e)
          EXPECT_NEAR(phi.row(q).dot(nodes.col(d).cwiseProduct(nodes.col(e))), xi(q, d) * xi(q, e), 1e-14);
    }
    // Gradients against central differences.
    for (int d = 0; d < dim; ++d) {
      Points<dim> plus = xi.row(q), minus = xi.row(q);
      plus(0, d) += 1e-6;
      minus(0, d) -= 1e-6;
      const MatrixX fd = (el.values(plus) - el.values(minus)) / 2e-6;
      for (int k = 0; k < n; ++k) EXPECT_NEAR(grad[d](q, k), fd(0, k), 1e-8) << "dof " << k << " d/dx" << d;
    }
  }
  // Order 1 does not reproduce x^2: the precision checks above can fail.
  if (order == 1) {
    double worst = 0;
    for (Index q = 0; q < xi.rows(); ++q)
      worst = std::max(worst, std::abs(phi.row(q).dot(nodes.col(0).cwiseAbs2()) - xi(q, 0) * xi(q, 0)));
    EXPECT_GT(worst, 1e-3);
  }
}

// The cell's shape functions restricted to facet f are the facet element's
// (in facet_dofs order); the others vanish on the facet.
template <int dim>
void check_facet_traces(CellType type, int order) {
  const LagrangeElement<dim> el(type, order);
  const auto& faces = cell_faces(type);
  const Points<dim> vertices = el.nodes().topRows(el.num_vertex_dofs());
  const std::vector<std::array<double, 2>> samples{{0.2, 0.1}, {0.3, 0.45}, {0.6, 0.3}};
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    const std::vector<int> dofs = facet_dofs(el, f);
    std::set<int> on_facet(dofs.begin(), dofs.end());
    EXPECT_EQ(on_facet.size(), dofs.size()) << "facet " << f;
    for (const auto& [s, t] : samples) {
      Point<dim> x = Point<dim>::Zero();
      VectorX trace;
      if constexpr (dim == 2) {
        x = (1 - s) * vertices.row(faces[f][0]).transpose() + s * vertices.row(faces[f][1]).transpose();
        trace.resize(order + 1);
        edge_shape_functions(order, s, trace.data());
      } else {
        const LagrangeElement<2> facet_el(facet_type(type), order);
        Points<2> st(1, 2);
        st << s, t;
        const MatrixX w = LagrangeElement<2>(facet_type(type), 1).values(st);
        for (std::size_t v = 0; v < faces[f].size(); ++v)
          x += w(0, static_cast<Index>(v)) * vertices.row(faces[f][v]).transpose();
        trace = facet_el.values(st).row(0).transpose();
      }
      ASSERT_EQ(trace.size(), static_cast<Index>(dofs.size()));
      const MatrixX phi = el.values(Points<dim>(x.transpose()));
      for (std::size_t k = 0; k < dofs.size(); ++k)
        EXPECT_NEAR(phi(0, dofs[k]), trace(static_cast<Index>(k)), 1e-14) << "facet " << f << " node " << k;
      for (int j = 0; j < el.num_dofs(); ++j)
        if (!on_facet.count(j)) {
          EXPECT_NEAR(phi(0, j), 0.0, 1e-14) << "facet " << f << " dof " << j;
        }
    }
  }
}

class Element2D : public ::testing::TestWithParam<ElementCase> {};
class Element3D : public ::testing::TestWithParam<ElementCase> {};

}  // namespace

TEST_P(Element2D, NodalPolynomialAndGradientProperties) {
  check_element<2>(GetParam().type, GetParam().order);
}
TEST_P(Element2D, FacetTracesAreTheEdgeShapeFunctions) {
  check_facet_traces<2>(GetParam().type, GetParam().order);
}
TEST_P(Element3D, NodalPolynomialAndGradientProperties) {
  check_element<3>(GetParam().type, GetParam().order);
}
TEST_P(Element3D, FacetTracesAreTheFacetElements) {
  check_facet_traces<3>(GetParam().type, GetParam().order);
}

INSTANTIATE_TEST_SUITE_P(Reference, Element2D,
                         ::testing::Values(ElementCase{CellType::triangle, 1},
                                           ElementCase{CellType::triangle, 2},
                                           ElementCase{CellType::quadrilateral, 1},
                                           ElementCase{CellType::quadrilateral, 2}),
                         case_name);
INSTANTIATE_TEST_SUITE_P(Reference, Element3D,
                         ::testing::Values(ElementCase{CellType::tetrahedron, 1},
                                           ElementCase{CellType::tetrahedron, 2},
                                           ElementCase{CellType::hexahedron, 1},
                                           ElementCase{CellType::hexahedron, 2}),
                         case_name);

TEST(LagrangeElement3D, DofCounts) {
  const LagrangeElement<3> p2(CellType::tetrahedron, 2), q2(CellType::hexahedron, 2);
  EXPECT_EQ(p2.num_dofs(), 10);
  EXPECT_EQ(p2.interior_dofs(), 0);
  EXPECT_EQ(p2.dofs_per_face(), 0);
  EXPECT_EQ(q2.num_dofs(), 27);
  EXPECT_EQ(q2.dofs_per_face(), 1);
  EXPECT_EQ(q2.interior_dofs(), 1);
  EXPECT_EQ(LagrangeElement<3>(CellType::hexahedron, 1).num_dofs(), 8);
  EXPECT_EQ(q2.name(), "Q2");
  EXPECT_EQ(p2.name(), "P2");
}

TEST(LagrangeElement3D, CellOfTheWrongDimensionIsAnError) {
  EXPECT_THROW(LagrangeElement<3>(CellType::triangle, 1), Error);
  EXPECT_THROW(LagrangeElement<2>(CellType::hexahedron, 1), Error);
  EXPECT_THROW(LagrangeElement<3>(CellType::tetrahedron, 3), Error);
}

// ---------------------------------------------------------------- topology

namespace {
template <int dim>
void check_topology(CellType type) {
  const Points<dim> v = LagrangeElement<dim>(type, 1).nodes();
  const Point<dim> centre = v.colwise().mean().transpose();
  std::set<std::pair<int, int>> edges;
  for (const auto& e : cell_edges(type)) edges.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
  EXPECT_EQ(edges.size(), cell_edges(type).size()) << to_string(type) << ": repeated edge";
  for (const auto& f : cell_faces(type)) {
    const Point<dim> a = v.row(f[0]).transpose(), b = v.row(f[1]).transpose();
    Point<dim> normal;
    if constexpr (dim == 2) {
      normal << (b - a)(1), -(b - a)(0);  // right of a -> b: outward for counter-clockwise cells
    } else {
      const Point<3> c = v.row(f[2]).transpose();
      normal = (b - a).cross(c - a);
      // Every vertex of the facet lies in its plane.
      for (int w : f) EXPECT_NEAR(normal.dot(v.row(w).transpose() - a), 0.0, 1e-14) << to_string(type);
    }
    EXPECT_GT(normal.dot(a - centre), 0.0) << to_string(type) << ": facet not outward";
    // The facet's boundary consists of cell edges.
    for (std::size_t k = 0; k < f.size(); ++k) {
      const int p = f[k], q = f[(k + 1) % f.size()];
      if (dim == 3) {
        EXPECT_TRUE(edges.count({std::min(p, q), std::max(p, q)})) << to_string(type);
      }
    }
  }
  // Euler characteristic of the cell's boundary: V - E + F = 2 in 3D; V = E in 2D.
  const int V = vertices_per_cell(type), E = static_cast<int>(edges.size()),
            F = static_cast<int>(cell_faces(type).size());
  EXPECT_EQ(dim == 3 ? V - E + F : V - E, dim == 3 ? 2 : 0) << to_string(type);
}
}  // namespace

TEST(ReferenceCell, FacetsAreOutwardAndTopologyIsConsistent) {
  check_topology<2>(CellType::triangle);
  check_topology<2>(CellType::quadrilateral);
  check_topology<3>(CellType::tetrahedron);
  check_topology<3>(CellType::hexahedron);
  EXPECT_EQ(cell_edges(CellType::hexahedron).size(), 12u);
  EXPECT_EQ(facet_type(CellType::hexahedron), CellType::quadrilateral);
  EXPECT_EQ(facet_type(CellType::tetrahedron), CellType::triangle);
  EXPECT_THROW(facet_type(CellType::triangle), Error);
}

// -------------------------------------------------------------- quadrature

namespace {
// Integral of x^a y^b z^c over the reference tetrahedron: a! b! c! / (a + b + c + 3)!.
double tetrahedron_monomial(int a, int b, int c) {
  return std::tgamma(a + 1) * std::tgamma(b + 1) * std::tgamma(c + 1) / std::tgamma(a + b + c + 4);
}
double hexahedron_monomial(int a, int b, int c) {
  return 1.0 / ((a + 1) * (b + 1) * (c + 1));
}
double quadrature_error(const QuadratureRule<3>& rule, CellType type, int a, int b, int c) {
  double s = 0;
  for (Index q = 0; q < rule.size(); ++q)
    s += rule.weights(q) * std::pow(rule.points(q, 0), a) * std::pow(rule.points(q, 1), b) *
         std::pow(rule.points(q, 2), c);
  return s - (type == CellType::tetrahedron ? tetrahedron_monomial(a, b, c) : hexahedron_monomial(a, b, c));
}
}  // namespace

TEST(Quadrature, GaussJacobiIsExactToDegree2nMinus1AndNotBeyond) {
  for (int alpha = 0; alpha <= 2; ++alpha)
    for (int n = 1; n <= 6; ++n) {
      const auto rule = gauss_jacobi(n, alpha);
      EXPECT_EQ(rule.degree, 2 * n - 1);
      // Integral of (1 - x)^alpha x^k over [0, 1] = k! alpha! / (k + alpha + 1)!.
      auto error = [&](int k) {
        double s = 0;
        for (Index q = 0; q < rule.size(); ++q) s += rule.weights(q) * std::pow(rule.points(q, 0), k);
        return s - std::tgamma(k + 1) * std::tgamma(alpha + 1) / std::tgamma(k + alpha + 2);
      };
      for (int k = 0; k <= 2 * n - 1; ++k) EXPECT_NEAR(error(k), 0.0, 1e-14) << "n=" << n << " k=" << k;
      EXPECT_GT(std::abs(error(2 * n)), 1e-10) << "n=" << n << " alpha=" << alpha;
    }
}

TEST(Quadrature, Rules3DAreExactToTheirStatedDegreeAndNotBeyond) {
  for (CellType type : {CellType::tetrahedron, CellType::hexahedron})
    for (int degree = 0; degree <= 9; ++degree) {
      const auto rule = cell_quadrature<3>(type, degree);
      const std::string what = to_string(type) + " degree " + std::to_string(degree);
      EXPECT_GE(rule.degree, degree) << what;
      EXPECT_LE(rule.degree, degree + 1) << what;
      EXPECT_GT(rule.weights.minCoeff(), 0.0) << what;
      // Strictly inside the cell: the map is evaluated there.
      for (Index q = 0; q < rule.size(); ++q) {
        EXPECT_GT(rule.points.row(q).minCoeff(), 0.0) << what;
        if (type == CellType::tetrahedron)
          EXPECT_LT(rule.points.row(q).sum(), 1.0) << what;
        else
          EXPECT_LT(rule.points.row(q).maxCoeff(), 1.0) << what;
      }
      const int p = rule.degree;
      // Exact for total degree <= p (tetrahedron), every exponent <= p (hexahedron).
      for (int a = 0; a <= p; ++a)
        for (int b = 0; b <= p; ++b)
          for (int c = 0; c <= p; ++c) {
            if (type == CellType::tetrahedron && a + b + c > p) continue;
            EXPECT_NEAR(quadrature_error(rule, type, a, b, c), 0.0, 1e-14)
                << what << ": x^" << a << " y^" << b << " z^" << c;
          }
      // Not exact one degree beyond, along every axis.
      for (int d = 0; d < 3; ++d) {
        int e[3] = {0, 0, 0};
        e[d] = p + 1;
        EXPECT_GT(std::abs(quadrature_error(rule, type, e[0], e[1], e[2])), 1e-8) << what << " axis " << d;
      }
    }
}

TEST(Quadrature, CellOfTheWrongDimensionIsAnError) {
  EXPECT_THROW(cell_quadrature<3>(CellType::triangle, 2), Error);
  EXPECT_THROW(cell_quadrature<2>(CellType::hexahedron, 2), Error);
  EXPECT_THROW(cell_quadrature<3>(CellType::tetrahedron, -1), Error);
}
