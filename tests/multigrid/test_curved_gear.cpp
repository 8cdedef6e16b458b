// The gear-like example the way the framework is meant to meet a curved
// boundary (examples/poisson_gear_curved.json): Ω0 is the 64-corner gear with
// straight edges, Ω1 the same gear with arcs and convex flanks, and the map
// keeps the corners. Then the geometric V-cycle with Chebyshev–SSOR needs an
// h-independent number of iterations for P1 and P2, unlike the square → gear
// map of examples/study_gear64.json, whose Jacobian is strongly anisotropic
// next to the vertices whose angle it changes (docs/multigrid.md).

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "core/mesh/polygon_mesher.hpp"
#include "io/run_config.hpp"
#include "mapping/make_map.hpp"
#include "multigrid/poisson_multigrid.hpp"
#include "multigrid_fixtures.hpp"

using namespace warpfem;
using S = multigrid::MultigridSettings;

namespace {

struct CurvedGear {
  mapping::MapSpec spec;
  mapping::MapPtr<2> map;
  warpfem::Mesh<2> coarse;
};

CurvedGear load_curved_gear() {
  const std::string file = "examples/poisson_gear_curved.json";  // tests run in the source directory
  CurvedGear g;
  g.spec = io::parse_required_map(io::ConfigNode(io::ConfigNode::parse_file(file), file));
  g.map = mapping::make_map(g.spec);
  g.coarse = warpfem::mesh_polygon(*g.spec.source, {.max_edge_length = 0.15});
  return g;
}

std::vector<int> iteration_counts(const CurvedGear& g, int order, int min_refinements, int max_refinements) {
  const fem::PoissonData<2> data = multigrid::test::unit_source_zero_dirichlet();
  std::vector<int> counts;
  for (int r = min_refinements; r <= max_refinements; ++r) {
    multigrid::PoissonMultigridOptions o;
    o.multigrid.smoother = S::Smoother::chebyshev_sor;
    o.finest_geometry = fem::GeometryStorage::streamed;
    multigrid::PoissonMultigridSolver<2> mg(PETSC_COMM_WORLD, g.coarse, r, g.map, order,
                                            warpfem::default_quadrature_degree(order), data, o);
    const auto report = mg.solve();
    EXPECT_TRUE(report.linear.converged);
    counts.push_back(report.linear.iterations);
  }
  return counts;
}

}  // namespace

TEST(CurvedGear, TheMapKeepsTheCornersAndBarelyDistorts) {
  const CurvedGear g = load_curved_gear();
  ASSERT_EQ(g.spec.source->size(), 192);
  // The corners (every third vertex) are not moved; the other vertices are.
  double corner_shift = 0, edge_shift = 0;
  for (Index i = 0; i < g.spec.source->size(); ++i) {
    const double d = (g.spec.source->vertex(i) - g.spec.target->vertex(i)).norm();
    double& shift = i % 3 == 0 ? corner_shift : edge_shift;
    shift = std::max(shift, d);
  }
  EXPECT_LT(corner_shift, 1e-12);
  EXPECT_GT(edge_shift, 1e-3);
  // At the coarse cells' centroids J_f is close to a rotation times a scaling.
  Points<2> x0(g.coarse.num_cells(), 2);
  for (Index c = 0; c < g.coarse.num_cells(); ++c)
    x0.row(c) = ((g.coarse.vertex(g.coarse.cells(c, 0)) + g.coarse.vertex(g.coarse.cells(c, 1)) +
                  g.coarse.vertex(g.coarse.cells(c, 2))) /
                 3.0)
                    .transpose();
  Jacobians<2> J;
  g.map->jacobian(x0, J);
  double worst_ratio = 1, smallest_det = 1e300;
  for (Index c = 0; c < J.rows(); ++c) {
    Eigen::Matrix2d Jc;
    Jc << J(c, 0), J(c, 1), J(c, 2), J(c, 3);  // row-major per point
    const Eigen::Vector2d sigma = Eigen::JacobiSVD<Eigen::Matrix2d>(Jc).singularValues();
    worst_ratio = std::max(worst_ratio, sigma(0) / sigma(1));
    smallest_det = std::min(smallest_det, Jc.determinant());
  }
  EXPECT_LT(worst_ratio, 1.5);
  EXPECT_GT(smallest_det, 0.5);
}

TEST(CurvedGear, ChebyshevSorIterationsDoNotDependOnTheMeshSize) {
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (size > 1) GTEST_SKIP() << "serial study (SSOR's counts depend on the partition)";
  const CurvedGear g = load_curved_gear();
  const std::vector<int> p1 = iteration_counts(g, 1, 1, 4);  // 1.6 k … 94 k DOFs
  const std::vector<int> p2 = iteration_counts(g, 2, 1, 3);  // 6.2 k … 94 k DOFs
  std::printf("curved gear, Chebyshev-SSOR: P1 %d %d %d %d, P2 %d %d %d\n", p1[0], p1[1], p1[2], p1[3], p2[0],
              p2[1], p2[2]);
  const auto [lo1, hi1] = std::minmax_element(p1.begin(), p1.end());
  const auto [lo2, hi2] = std::minmax_element(p2.begin(), p2.end());
  EXPECT_LE(*hi1 - *lo1, 2);
  EXPECT_LE(*hi1, 12);
  EXPECT_LE(*hi2 - *lo2, 2);
  EXPECT_LE(*hi2, 15);
}
