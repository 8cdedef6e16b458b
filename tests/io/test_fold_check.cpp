// The fold check of written cells: its Bernstein shortcut on simplices never
// changes the decision of the lattice check it skips, and it tells folded
// cells from unfolded ones.

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "fem/postprocessing/fold_check.hpp"
#include "fem/reference/lagrange_element.hpp"

using namespace warpfem;

namespace {

// The nodes of the straight cell through `vertices` (element node order).
template <int dim>
std::vector<Point<dim>> straight_nodes(const fem::LagrangeElement<dim>& element,
                                       const std::vector<Point<dim>>& vertices) {
  const fem::LagrangeElement<dim> linear(element.cell_type(), 1);
  const MatrixX w = linear.values(element.nodes());
  std::vector<Point<dim>> x(static_cast<std::size_t>(element.num_dofs()), Point<dim>::Zero());
  for (int k = 0; k < element.num_dofs(); ++k)
    for (int v = 0; v < element.num_vertex_dofs(); ++v)
      x[static_cast<std::size_t>(k)] += w(k, v) * vertices[static_cast<std::size_t>(v)];
  return x;
}

template <int dim>
std::vector<Point<dim>> reference_vertices(const fem::LagrangeElement<dim>& element) {
  std::vector<Point<dim>> v;
  for (int k = 0; k < element.num_vertex_dofs(); ++k) v.push_back(element.nodes().row(k).transpose());
  return v;
}

// Random cells, from straight to strongly bent, agree with the lattice check,
// and both outcomes occur.
template <int dim>
void expect_agreement(CellType type, int order) {
  const fem::LagrangeElement<dim> element(type, order);
  const fem::FoldCheck<dim> check(element);
  std::mt19937 rng(17 + 10 * order + static_cast<int>(type));
  std::uniform_real_distribution<double> u(-1, 1);
  int folded = 0, unfolded = 0;
  for (const double bend : {0.0, 0.05, 0.15, 0.3, 0.6}) {
    for (int trial = 0; trial < 400; ++trial) {
      std::vector<Point<dim>> vertices = reference_vertices(element);
      for (auto& v : vertices)
        for (int d = 0; d < dim; ++d) v(d) += (0.15 + bend) * u(rng);
      std::vector<Point<dim>> x = straight_nodes(element, vertices);
      for (std::size_t k = static_cast<std::size_t>(element.num_vertex_dofs()); k < x.size(); ++k)
        for (int d = 0; d < dim; ++d) x[k](d) += bend * u(rng);
      const bool f = check.folds(x.data());
      ASSERT_EQ(f, check.folds_on_lattice(x.data())) << "bend " << bend << ", trial " << trial;
      (f ? folded : unfolded) += 1;
    }
  }
  EXPECT_GT(folded, 50);
  EXPECT_GT(unfolded, 50);
}

}  // namespace

TEST(FoldCheck, ShortcutAgreesWithTheLatticeOnTriangles) {
  expect_agreement<2>(CellType::triangle, 2);
  expect_agreement<2>(CellType::triangle, 1);
}

TEST(FoldCheck, ShortcutAgreesWithTheLatticeOnTetrahedra) {
  expect_agreement<3>(CellType::tetrahedron, 2);
}

TEST(FoldCheck, QuadrilateralsUseTheLattice) {
  expect_agreement<2>(CellType::quadrilateral, 2);
}

TEST(FoldCheck, TellsFoldedFromStraightCells) {
  const fem::LagrangeElement<2> element(CellType::triangle, 2);
  const fem::FoldCheck<2> check(element);
  std::vector<Point<2>> vertices = reference_vertices(element);
  std::vector<Point<2>> x = straight_nodes(element, vertices);
  EXPECT_FALSE(check.folds(x.data()));
  // Mirrored: negative orientation everywhere.
  std::swap(vertices[1], vertices[2]);
  std::vector<Point<2>> mirrored = straight_nodes(element, vertices);
  EXPECT_TRUE(check.folds(mirrored.data()));
  // The midpoint of edge (0, 1) pulled across the opposite vertex (0, 1).
  x[3] = Point<2>(0.5, 1.2);
  EXPECT_TRUE(check.folds(x.data()));
}
