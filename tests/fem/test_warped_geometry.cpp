// WarpedGeometry storage modes: the streamed geometry (recomputed per pass) must
// give exactly what the cached one stores, and everything built on it (Poisson
// matrix, load, errors, area) must not depend on the mode.

#include <gtest/gtest.h>
#include <petscksp.h>

#include <memory>

#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/quadrature.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "fem/physics/poisson.hpp"
#include "mapping/barycentric_map.hpp"
#include "mapping/make_map.hpp"

using namespace warpfem;

namespace {

const Polygon& pentagon() {
  static const Polygon p = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}}, "pentagon");
  return p;
}

mapping::MapPtr<2> concave_composite() {
  mapping::MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = pentagon();
  spec.target = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 0.75}, {0, 1}}, "bent pentagon");
  return mapping::make_map(spec);
}

std::vector<Index> all_cells(const warpfem::Mesh<2>& mesh) {
  std::vector<Index> cells(static_cast<std::size_t>(mesh.num_cells()));
  for (Index c = 0; c < mesh.num_cells(); ++c) cells[static_cast<std::size_t>(c)] = c;
  return cells;
}

}  // namespace

TEST(WarpedGeometryStorage, StreamedChunksEqualTheCachedArrays) {
  // 90 x 90 x 2 triangles x 6 points = 97,200 points: more than one streamed chunk.
  const warpfem::Mesh<2> mesh = warpfem::structured_mesh(pentagon(), 90, 90, warpfem::CellType::triangle);
  const auto map = concave_composite();
  const auto rule = warpfem::cell_quadrature<2>(mesh.cell_type, 4);
  const fem::WarpedGeometry<2> cached(mesh, all_cells(mesh), rule, *map);
  const fem::WarpedGeometry<2> streamed(mesh, all_cells(mesh), rule, *map, fem::GeometryStorage::streamed);
  ASSERT_GT(cached.num_cells() * cached.points_per_cell(), fem::WarpedGeometry<2>::chunk_points());
  int chunks = 0;
  Index next_cell = 0;
  double max_diff = 0;
  streamed.for_each_chunk([&](const fem::GeometryChunk<2>& g) {
    ++chunks;
    EXPECT_EQ(g.first_cell(), next_cell);  // in order, no gaps
    next_cell += g.num_cells();
    for (Index i = 0; i < g.num_cells(); ++i)
      for (Index q = 0; q < streamed.points_per_cell(); ++q) {
        const Index p = g.at(i, q), pc = cached.at(g.first_cell() + i, q);
        for (int d = 0; d < 2; ++d)
          max_diff = std::max(max_diff, std::abs(g.x(p, d) - cached.physical_points()(pc, d)));
        for (int k = 0; k < 4; ++k)
          max_diff =
              std::max(max_diff, std::abs(g.inverse_transpose(p, k) - cached.inverse_transpose()(pc, k)));
        max_diff = std::max(max_diff, std::abs(g.JxW(p) - cached.JxW()(pc)));
      }
  });
  EXPECT_GE(chunks, 2);
  EXPECT_EQ(next_cell, cached.num_cells());
  EXPECT_LE(max_diff, 1e-14);
  // The cached geometry is one chunk over its own arrays.
  int cached_chunks = 0;
  cached.for_each_chunk([&](const fem::GeometryChunk<2>& g) {
    ++cached_chunks;
    EXPECT_EQ(g.num_cells(), cached.num_cells());
    EXPECT_EQ(g.JxW(g.at(7, 3)), cached.JxW()(cached.at(7, 3)));
  });
  EXPECT_EQ(cached_chunks, 1);
}

TEST(WarpedGeometryStorage, StreamedGeometryHasNoArrays) {
  const warpfem::Mesh<2> mesh = warpfem::structured_mesh(pentagon(), 4, 4, warpfem::CellType::quadrilateral);
  const auto map = concave_composite();
  const fem::WarpedGeometry<2> g(mesh, all_cells(mesh), warpfem::cell_quadrature<2>(mesh.cell_type, 4), *map,
                                 fem::GeometryStorage::streamed);
  EXPECT_THROW(g.JxW(), Error);
  EXPECT_THROW(g.physical_points(), Error);
  EXPECT_THROW(g.inverse_transpose(), Error);
}

TEST(WarpedGeometryStorage, FoldingMapIsReportedByTheFirstStreamedPass) {
  // The one-step mean value map of the thesis' §2.1.2 counterexample folds: the
  // square (a diamond) with one vertex pulled inside, past the opposite diagonal.
  const Polygon diamond = Polygon::checked({{-1, 0}, {0, -1}, {1, 0}, {0, 1}}, "diamond");
  const Polygon dart = Polygon::checked({{-1, 0}, {0, -1}, {-0.6, 0}, {0, 1}}, "dart");
  const auto map = std::make_shared<const mapping::BarycentricMap>(diamond, dart);
  const warpfem::Mesh<2> mesh = warpfem::mesh_polygon(diamond, {.max_edge_length = 0.1});
  const auto rule = warpfem::cell_quadrature<2>(mesh.cell_type, 2);
  EXPECT_THROW(fem::WarpedGeometry<2>(mesh, all_cells(mesh), rule, *map), Error);
  const fem::WarpedGeometry<2> streamed(mesh, all_cells(mesh), rule, *map, fem::GeometryStorage::streamed);
  try {
    streamed.for_each_chunk([](const fem::GeometryChunk<2>&) {});
    ADD_FAILURE() << "a folding map must be reported";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("inverted or degenerate"), std::string::npos) << e.what();
  }
}

TEST(WarpedGeometryStorage, PoissonDoesNotDependOnTheStorage) {
  const warpfem::Mesh<2> mesh = warpfem::structured_mesh(pentagon(), 12, 12, warpfem::CellType::triangle);
  const auto map = concave_composite();
  fem::PoissonData<2> data;
  data.source = [](const Point<2>& x, double) { return 1 + x.x() * x.y(); };
  data.dirichlet.push_back({.edges = {}, .value = [](const Point<2>& x, double) { return x.x(); }});
  for (int order : {1, 2}) {
    fem::PoissonProblem<2> cached(MPI_COMM_SELF, mesh, map, order, 2 * order + 2, data);
    fem::PoissonProblem<2> streamed(MPI_COMM_SELF, mesh, map, order, 2 * order + 2, data,
                                    fem::GeometryStorage::streamed);
    // The area assemble() sums on the way is the one a pass of its own gives, bit for bit.
    const double area_by_pass = cached.area();
    EXPECT_GT(area_by_pass, 0.5);
    cached.assemble();
    EXPECT_EQ(cached.area(), area_by_pass) << "P" << order;
    streamed.assemble();
    PetscReal a_norm = 0, diff = 0, b_norm = 0;
    WARPFEM_PETSC_CHECK(MatNorm(cached.matrix(), NORM_FROBENIUS, &a_norm));
    WARPFEM_PETSC_CHECK(MatAXPY(streamed.matrix(), -1.0, cached.matrix(), SAME_NONZERO_PATTERN));
    WARPFEM_PETSC_CHECK(MatNorm(streamed.matrix(), NORM_FROBENIUS, &diff));
    EXPECT_LE(diff, 1e-13 * a_norm) << "P" << order;
    WARPFEM_PETSC_CHECK(VecNorm(cached.rhs(), NORM_2, &b_norm));
    WARPFEM_PETSC_CHECK(VecAXPY(streamed.rhs(), -1.0, cached.rhs()));
    WARPFEM_PETSC_CHECK(VecNorm(streamed.rhs(), NORM_2, &diff));
    EXPECT_LE(diff, 1e-13 * b_norm) << "P" << order;
    // Errors against u = x (harmonic, so not the solution: both see the same nonzero error) and area.
    streamed.assemble();  // restore the operators changed above
    petsc::LinearSolveOptions lu;
    lu.direct_below = 1 << 20;  // LU for these few DOFs
    cached.solve(lu);
    streamed.solve(lu);
    const fem::ScalarFunction<2> u = [](const Point<2>& x, double) { return x.x(); };
    const fem::GradientFunction<2> du = [](const Point<2>&, double) { return Point<2>(1, 0); };
    const fem::ErrorNorms ec = cached.errors(u, du), es = streamed.errors(u, du);
    EXPECT_GT(ec.l2, 1e-3);
    EXPECT_NEAR(es.l2, ec.l2, 1e-12 * ec.l2);
    EXPECT_NEAR(es.h1_semi, ec.h1_semi, 1e-12 * ec.h1_semi);
    EXPECT_NEAR(streamed.area(), cached.area(), 1e-14);
  }
}

// A ConstantFunction source skips the per-point calls; the load vector must be
// the one a plain lambda with the same value gives.
TEST(WarpedGeometryStorage, ConstantSourceAssemblesLikeAPointwiseOne) {
  const warpfem::Mesh<2> mesh = warpfem::structured_mesh(pentagon(), 10, 10, warpfem::CellType::triangle);
  const auto map = concave_composite();
  for (int order : {1, 2}) {
    fem::PoissonData<2> pointwise, constant;
    pointwise.source = [](const Point<2>&, double) { return 2.5; };
    constant.source = fem::ConstantFunction{2.5};
    ASSERT_NE(constant.source.target<fem::ConstantFunction>(), nullptr);
    for (auto* d : {&pointwise, &constant})
      d->dirichlet.push_back({.edges = {0}, .value = [](const Point<2>& x, double) { return x.y(); }});
    fem::PoissonProblem<2> a(MPI_COMM_SELF, mesh, map, order, 2 * order + 2, pointwise,
                             fem::GeometryStorage::streamed);
    fem::PoissonProblem<2> b(MPI_COMM_SELF, mesh, map, order, 2 * order + 2, constant,
                             fem::GeometryStorage::streamed);
    a.assemble();
    b.assemble();
    PetscReal norm = 0, diff = 0;
    WARPFEM_PETSC_CHECK(VecNorm(a.rhs(), NORM_2, &norm));
    WARPFEM_PETSC_CHECK(VecAXPY(b.rhs(), -1.0, a.rhs()));
    WARPFEM_PETSC_CHECK(VecNorm(b.rhs(), NORM_2, &diff));
    EXPECT_GT(norm, 0.1);
    EXPECT_LE(diff, 1e-14 * norm) << "P" << order;
  }
}
