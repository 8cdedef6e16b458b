// 3D smoke test of the dimension templates: Q1 Poisson on structured
// hexahedral meshes of the unit cube, identity map, manufactured solution,
// assembled through WarpedGeometry<3>, CellValues<3>, integrate_cells and
// petsc::MatrixAssembler; the L2 error must converge at rate 2.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/csr_matrix.hpp"
#include "core/petsc/linear_solve.hpp"
#include "core/petsc/matrix_assembler.hpp"
#include "fem/assembly/integrate.hpp"
#include "fem/physics/poisson_kernel.hpp"

using namespace warpfem;

namespace {

constexpr double pi = std::numbers::pi;
double exact(const Point<3>& x) {
  return std::sin(pi * x.x()) * std::sin(pi * x.y()) * std::sin(pi * x.z());
}

struct Result {
  double l2 = 0, h1 = 0;
  int iterations = 0;
};

/// −Δu = 3π² u_exact, u = 0 on the boundary, Q1 (or P1) on an n³ box mesh.
Result solve_on_cube(int n, warpfem::CellType type) {
  const warpfem::Mesh<3> mesh =
      warpfem::structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), {n, n, n}, type);
  const fem::LagrangeElement<3> element(type, 1);
  const mapping::IdentityMap<3> map;
  std::vector<Index> cells(static_cast<std::size_t>(mesh.num_cells()));
  for (Index c = 0; c < mesh.num_cells(); ++c) cells[static_cast<std::size_t>(c)] = c;
  const fem::WarpedGeometry<3> geometry(mesh, cells, warpfem::cell_quadrature<3>(type, 4), map);

  // Q1/P1: the DOFs are the vertices. Pattern: the vertices sharing a cell.
  const Index nv = mesh.num_vertices();
  std::vector<std::set<PetscInt>> rows(static_cast<std::size_t>(nv));
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (Index a = 0; a < mesh.cells.cols(); ++a)
      for (Index b = 0; b < mesh.cells.cols(); ++b)
        rows[static_cast<std::size_t>(mesh.cells(c, a))].insert(mesh.cells(c, b));
  petsc::OwnedRows pattern;
  pattern.row_ptr.push_back(0);
  for (const auto& r : rows) {
    pattern.cols.insert(pattern.cols.end(), r.begin(), r.end());
    pattern.row_ptr.push_back(static_cast<PetscInt>(pattern.cols.size()));
  }
  const auto N = static_cast<PetscInt>(nv);
  petsc::Matrix A =
      petsc::adopt_owned_rows(PETSC_COMM_SELF, std::move(pattern), N, 0, N, N, {.inodes = false});
  petsc::Vector b, u;
  WARPFEM_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, N, b.out()));
  WARPFEM_PETSC_CHECK(VecDuplicate(b.get(), u.out()));

  std::vector<char> fixed(static_cast<std::size_t>(nv), 0);
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f)
    for (Index k = 0; k < mesh.boundary_facets.cols(); ++k)
      fixed[static_cast<std::size_t>(mesh.boundary_facets(f, k))] = 1;

  {
    petsc::MatrixAssembler assembler(A.get(), b.get());
    std::vector<PetscInt> idx(static_cast<std::size_t>(element.num_dofs()));
    std::vector<double> K, F;
    fem::CellValues<3> values(element, geometry, fem::CellValues<3>::update_gradients);
    fem::integrate_cells(
        geometry, values,
        fem::PoissonKernel<3>([](const Point<3>& x) { return 3 * pi * pi * exact(x); },
                              [&](const fem::CellValues<3>& v, const double* ke, const double* fe) {
                                const int m = v.num_dofs();
                                K.assign(ke, ke + m * m);
                                F.assign(fe, fe + m);
                                for (int k = 0; k < m; ++k) {
                                  idx[static_cast<std::size_t>(k)] = mesh.cells(v.cell(), k);
                                  if (!fixed[static_cast<std::size_t>(idx[static_cast<std::size_t>(k)])])
                                    continue;
                                  for (int r = 0; r < m; ++r)
                                    K[static_cast<std::size_t>(r * m + k)] =
                                        K[static_cast<std::size_t>(k * m + r)] = 0;
                                  F[static_cast<std::size_t>(k)] = 0;  // homogeneous data: no lifting
                                }
                                assembler.add(m, idx.data(), K.data(), F.data());
                              }));
    for (Index d = 0; d < nv; ++d)
      if (fixed[static_cast<std::size_t>(d)]) assembler.set_diagonal(static_cast<PetscInt>(d), 1.0);
    assembler.finish();
  }
  const auto report = petsc::solve_linear_system(A.get(), b.get(), u.get(),
                                                 {.ksp_type = "cg",
                                                  .pc_type = "gamg",
                                                  .rtol = 1e-10,
                                                  .atol = 1e-50,
                                                  .max_iterations = 1000,
                                                  .prefix = "",
                                                  .direct_below = 500});

  const PetscScalar* uh = nullptr;
  WARPFEM_PETSC_CHECK(VecGetArrayRead(u.get(), &uh));
  std::vector<double> ue(static_cast<std::size_t>(element.num_dofs()));
  Result r;
  r.iterations = report.iterations;
  double l2 = 0, h1 = 0;
  fem::CellValues<3> values(element, geometry, fem::CellValues<3>::update_gradients);
  fem::integrate_cells(geometry, values,
                       fem::make_kernel(
                           [&](const fem::CellValues<3>& v) {
                             for (int k = 0; k < v.num_dofs(); ++k)
                               ue[static_cast<std::size_t>(k)] = uh[mesh.cells(v.cell(), k)];
                             return true;
                           },
                           [&](const fem::CellValues<3>& v, Index q) {
                             const Point<3> x = v.point(q);
                             const Point<3> grad(
                                 pi * std::cos(pi * x.x()) * std::sin(pi * x.y()) * std::sin(pi * x.z()),
                                 pi * std::sin(pi * x.x()) * std::cos(pi * x.y()) * std::sin(pi * x.z()),
                                 pi * std::sin(pi * x.x()) * std::sin(pi * x.y()) * std::cos(pi * x.z()));
                             l2 += v.JxW(q) * std::pow(v.value(q, ue.data()) - exact(x), 2);
                             h1 += v.JxW(q) * (v.gradient(q, ue.data()) - grad).squaredNorm();
                           },
                           [](const fem::CellValues<3>&) {}));
  WARPFEM_PETSC_CHECK(VecRestoreArrayRead(u.get(), &uh));
  r.l2 = std::sqrt(l2);
  r.h1 = std::sqrt(h1);
  return r;
}

class Poisson3d : public ::testing::TestWithParam<warpfem::CellType> {};

}  // namespace

TEST_P(Poisson3d, FirstOrderRatesOnTheUnitCube) {
  // Kuhn tetrahedra of a 4³ grid are still pre-asymptotic (L2 rate 1.83 to 8³): start finer.
  const int n0 = GetParam() == warpfem::CellType::hexahedron ? 4 : 6;
  std::vector<Result> results;
  for (int n : {n0, 2 * n0, 4 * n0}) results.push_back(solve_on_cube(n, GetParam()));
  for (std::size_t i = 1; i < results.size(); ++i) {
    const double l2_rate = std::log2(results[i - 1].l2 / results[i].l2);
    const double h1_rate = std::log2(results[i - 1].h1 / results[i].h1);
    EXPECT_GE(l2_rate, 1.9) << "level " << i << ": " << results[i - 1].l2 << " -> " << results[i].l2;
    EXPECT_GE(h1_rate, 0.95) << "level " << i;
    EXPECT_LT(results[i].iterations, 40);
  }
}

INSTANTIATE_TEST_SUITE_P(Cells, Poisson3d,
                         ::testing::Values(warpfem::CellType::hexahedron, warpfem::CellType::tetrahedron),
                         [](const auto& info) { return warpfem::to_string(info.param); });
