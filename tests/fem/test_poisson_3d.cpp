// 3D smoke test of the dimension templates: P1/P2 Poisson on Kuhn tetrahedra
// and Q1/Q2 on hexahedra of the unit cube, identity map, manufactured
// solution, numbered by DofMap<3> and DofDistribution<3> (pattern, boundary
// DOFs from facet_dofs), assembled through WarpedGeometry<3>, CellValues<3>,
// integrate_cells and petsc::MatrixAssembler; the errors must converge at the
// element's rates (L2 order + 1, H1 order).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "core/petsc/csr_matrix.hpp"
#include "core/petsc/linear_solve.hpp"
#include "core/petsc/matrix_assembler.hpp"
#include "fem/assembly/integrate.hpp"
#include "fem/dofs/dof_distribution.hpp"
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

/// −Δu = 3π² u_exact, u = 0 on the boundary, P`order` / Q`order` on an n³ box mesh.
Result solve_on_cube(int n, warpfem::CellType type, int order) {
  const warpfem::Mesh<3> mesh =
      warpfem::structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), {n, n, n}, type);
  const fem::LagrangeElement<3> element(type, order);
  const mapping::IdentityMap<3> map;
  std::vector<Index> cells(static_cast<std::size_t>(mesh.num_cells()));
  for (Index c = 0; c < mesh.num_cells(); ++c) cells[static_cast<std::size_t>(c)] = c;
  const fem::WarpedGeometry<3> geometry(mesh, cells, warpfem::cell_quadrature<3>(type, 2 * order + 2), map);

  const fem::DofMap<3> dofs(mesh, element);
  const fem::DofDistribution<3> dist(PETSC_COMM_SELF, mesh, dofs);
  petsc::OwnedRows pattern;
  dist.sparsity(mesh, dofs, pattern.row_ptr, pattern.cols);
  const auto N = dist.num_global();
  petsc::Matrix A =
      petsc::adopt_owned_rows(PETSC_COMM_SELF, std::move(pattern), N, 0, N, N, {.inodes = false});
  petsc::Vector b, u;
  WARPFEM_PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, N, b.out()));
  WARPFEM_PETSC_CHECK(VecDuplicate(b.get(), u.out()));

  // Fixed: the PETSc rows of every DOF on a boundary facet.
  std::vector<char> fixed(static_cast<std::size_t>(N), 0);
  for (Index f = 0; f < mesh.num_boundary_facets(); ++f)
    for (const Index d : dofs.facet_dofs(mesh, f)) fixed[static_cast<std::size_t>(dist.global(d))] = 1;
  const auto cell_rows = [&](Index c, int k) { return dist.global(dofs.cell_dofs()(c, k)); };

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
                                  idx[static_cast<std::size_t>(k)] = cell_rows(v.cell(), k);
                                  if (!fixed[static_cast<std::size_t>(idx[static_cast<std::size_t>(k)])])
                                    continue;
                                  for (int r = 0; r < m; ++r)
                                    K[static_cast<std::size_t>(r * m + k)] =
                                        K[static_cast<std::size_t>(k * m + r)] = 0;
                                  F[static_cast<std::size_t>(k)] = 0;  // homogeneous data: no lifting
                                }
                                assembler.add(m, idx.data(), K.data(), F.data());
                              }));
    for (PetscInt d = 0; d < N; ++d)
      if (fixed[static_cast<std::size_t>(d)]) assembler.set_diagonal(d, 1.0);
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
                               ue[static_cast<std::size_t>(k)] = uh[cell_rows(v.cell(), k)];
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

struct Case {
  warpfem::CellType type;
  int order;
  int n0;      ///< coarsest grid (the rates are measured on n0, 2 n0, ...)
  int levels;  ///< grids n0 · 2^k, k < levels
  double l2_rate, h1_rate;
};

class Poisson3d : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(Poisson3d, RatesOnTheUnitCube) {
  const Case& p = GetParam();
  std::vector<Result> results;
  for (int k = 0; k < p.levels; ++k) results.push_back(solve_on_cube(p.n0 << k, p.type, p.order));
  for (std::size_t i = 1; i < results.size(); ++i) {
    const double l2_rate = std::log2(results[i - 1].l2 / results[i].l2);
    const double h1_rate = std::log2(results[i - 1].h1 / results[i].h1);
    EXPECT_GE(l2_rate, p.l2_rate) << "level " << i << ": " << results[i - 1].l2 << " -> " << results[i].l2;
    EXPECT_GE(h1_rate, p.h1_rate) << "level " << i << ": " << results[i - 1].h1 << " -> " << results[i].h1;
    EXPECT_LT(results[i].iterations, 40);
  }
}

// Kuhn tetrahedra are pre-asymptotic on coarse grids (P1: L2 rate 1.83 from 4³
// to 8³; P2: H1 rate 1.76 from 2³ to 4³, 1.86 from 3³ to 6³): start finer.
INSTANTIATE_TEST_SUITE_P(Cells, Poisson3d,
                         ::testing::Values(Case{warpfem::CellType::hexahedron, 1, 4, 3, 1.9, 0.95},
                                           Case{warpfem::CellType::tetrahedron, 1, 6, 3, 1.9, 0.95},
                                           Case{warpfem::CellType::hexahedron, 2, 2, 3, 2.85, 1.9},
                                           Case{warpfem::CellType::tetrahedron, 2, 4, 2, 2.85, 1.9}),
                         [](const auto& info) {
                           return warpfem::to_string(info.param.type) + "_order" +
                                  std::to_string(info.param.order);
                         });
