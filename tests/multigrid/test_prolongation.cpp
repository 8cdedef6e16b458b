// Prolongation between nested levels: exact for polynomials of the space (also
// on two ranks, as test_mpi_prolongation), and consistent with the eliminated
// Dirichlet rows (PᵀAP = rediscretized A).

#include <gtest/gtest.h>

#include <functional>

#include "core/petsc/check.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/hierarchy/mesh_factory.hpp"
#include "fem/hierarchy/mesh_hierarchy.hpp"
#include "multigrid/prolongation.hpp"
#include "multigrid_fixtures.hpp"

using namespace warpfem;
using multigrid::test::coarse_l_shape;

namespace {

using Polynomial = std::function<double(const Point<2>&)>;

struct Case {
  warpfem::CellType type;
  int order;
};

std::string name(const ::testing::TestParamInfo<Case>& info) {
  return (info.param.type == warpfem::CellType::triangle ? "P" : "Q") + std::to_string(info.param.order);
}

petsc::Vector interpolate(const fem::DofMap<2>& dofs, const fem::DofDistribution<2>& dist,
                          const Polynomial& g) {
  petsc::Vector v = dist.create_vector();
  for (Index d = 0; d < dofs.num_dofs(); ++d)
    if (dist.owns(d)) {
      const PetscInt row = dist.global(d);
      const PetscScalar value = g(dofs.dof_points().row(d).transpose());
      WARPFEM_PETSC_CHECK(VecSetValues(v.get(), 1, &row, &value, INSERT_VALUES));
    }
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(v.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(v.get()));
  return v;
}

/// max_i |(P g_coarse)_i − g(x_i)| over the finest level of a 3-level hierarchy (both prolongations).
double prolongation_error(const Case& c, const Polynomial& g) {
  const fem::MeshHierarchy<2> h(coarse_l_shape(c.type, 0.6), 2);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  // On two ranks (test_mpi_prolongation) the levels above the base are nested blocks.
  const auto parts = fem::nested_level_partitions(h, size, 4);
  const auto distribute = [&](int l, const fem::DofMap<2>& dofs) {
    const fem::LevelPartition& p = parts[static_cast<std::size_t>(l)];
    return p.blocks ? fem::DofDistribution<2>(MPI_COMM_WORLD, h.levels[l], dofs, *p.blocks)
                    : fem::DofDistribution<2>(MPI_COMM_WORLD, h.levels[l], dofs, p.cell_owner);
  };
  double worst = 0;
  for (int l = 1; l < h.num_levels(); ++l) {
    const fem::LagrangeElement<2> element(c.type, c.order);
    const fem::DofMap<2> cdofs(h.levels[l - 1], element), fdofs(h.levels[l], element);
    const fem::DofDistribution<2> cdist = distribute(l - 1, cdofs), fdist = distribute(l, fdofs);
    const petsc::Matrix P = multigrid::assemble_prolongation(h, l, {.dofs = &cdofs, .distribution = &cdist},
                                                             {.dofs = &fdofs, .distribution = &fdist});
    const petsc::Vector uc = interpolate(cdofs, cdist, g), expected = interpolate(fdofs, fdist, g);
    petsc::Vector uf = fdist.create_vector();
    WARPFEM_PETSC_CHECK(MatMult(P.get(), uc.get(), uf.get()));
    WARPFEM_PETSC_CHECK(VecAXPY(uf.get(), -1.0, expected.get()));
    PetscReal e = 0;
    WARPFEM_PETSC_CHECK(VecNorm(uf.get(), NORM_INFINITY, &e));
    worst = std::max(worst, static_cast<double>(e));
  }
  return worst;
}

}  // namespace

class Prolongation : public ::testing::TestWithParam<Case> {};

TEST_P(Prolongation, ReproducesLinearFunctionsExactly) {
  const double e = prolongation_error(GetParam(), [](const Point<2>& x) { return 3 - x.x() + 2 * x.y(); });
  EXPECT_LT(e, 1e-12);
}

TEST_P(Prolongation, ReproducesQuadraticsExactlyForOrderTwo) {
  const Polynomial q = [](const Point<2>& x) {
    return x.x() * x.x() - 3 * x.x() * x.y() + 0.5 * x.y() * x.y() + x.y();
  };
  const double e = prolongation_error(GetParam(), q);
  if (GetParam().order == 2)
    EXPECT_LT(e, 1e-12);
  else
    EXPECT_GT(e, 1e-3) << "order 1 cannot reproduce quadratics: the test would not detect anything";
}

INSTANTIATE_TEST_SUITE_P(Elements, Prolongation,
                         ::testing::Values(Case{warpfem::CellType::triangle, 1},
                                           Case{warpfem::CellType::triangle, 2},
                                           Case{warpfem::CellType::quadrilateral, 1},
                                           Case{warpfem::CellType::quadrilateral, 2}),
                         name);

class GalerkinConsistency : public ::testing::TestWithParam<Case> {};

// With the identity map on triangles and rectangles, integration is exact and the
// spaces are nested, so PᵀA_fP must equal the rediscretized coarse matrix,
// Dirichlet block included. This fails if Dirichlet rows/columns of P are wrong.
TEST_P(GalerkinConsistency, GalerkinCoarseOperatorEqualsRediscretization) {
  const Case c = GetParam();
  // Quadrilaterals: rectangles (a structured grid), so that the integrands are polynomials.
  const bool triangles = c.type == warpfem::CellType::triangle;
  const Polygon rectangle = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {0, 1}});
  const warpfem::Mesh<2> mesh =
      triangles ? coarse_l_shape(c.type, 0.5) : warpfem::structured_mesh(rectangle, 5, 3, c.type);
  const fem::MeshHierarchy<2> h(mesh, 1);
  const auto map = std::make_shared<mapping::IdentityMap<2>>();
  // Triangles: boundary parts selected by facet tag; rectangles: per node on the polygon (as apps/ does).
  const fem::PoissonData<2> data =
      multigrid::test::mixed_problem(triangles ? std::nullopt : std::optional(rectangle));
  fem::PoissonProblem<2> coarse(MPI_COMM_SELF, h.levels[0], map, c.order, 2 * c.order + 2, data);
  fem::PoissonProblem<2> fine(MPI_COMM_SELF, h.levels[1], map, c.order, 2 * c.order + 2, data);
  coarse.assemble();
  fine.assemble();
  const std::vector<char> cmask = coarse.constrained().front();
  const std::vector<char> fmask = fine.constrained().front();
  const petsc::Matrix P = multigrid::assemble_prolongation(
      h, 1, {.dofs = &coarse.dofs(), .distribution = &coarse.distribution(), .dirichlet = cmask},
      {.dofs = &fine.dofs(), .distribution = &fine.distribution(), .dirichlet = fmask});
  petsc::Matrix galerkin;
  WARPFEM_PETSC_CHECK(MatPtAP(fine.matrix(), P.get(), MAT_INITIAL_MATRIX, 2.0, galerkin.out()));
  PetscReal scale = 0, diff = 0;
  WARPFEM_PETSC_CHECK(MatNorm(coarse.matrix(), NORM_INFINITY, &scale));
  WARPFEM_PETSC_CHECK(MatAXPY(galerkin.get(), -1.0, coarse.matrix(), DIFFERENT_NONZERO_PATTERN));
  WARPFEM_PETSC_CHECK(MatNorm(galerkin.get(), NORM_INFINITY, &diff));
  EXPECT_LT(diff, 1e-12 * scale) << "‖PᵀAP − A_coarse‖∞ = " << diff;
  // Both Dirichlet masks must be non-trivial, otherwise the test proves nothing about them.
  EXPECT_GT(std::count(cmask.begin(), cmask.end(), 1), 0);
  EXPECT_LT(std::count(cmask.begin(), cmask.end(), 1), static_cast<long>(cmask.size()));
}

INSTANTIATE_TEST_SUITE_P(Elements, GalerkinConsistency,
                         ::testing::Values(Case{warpfem::CellType::triangle, 1},
                                           Case{warpfem::CellType::triangle, 2},
                                           Case{warpfem::CellType::quadrilateral, 1},
                                           Case{warpfem::CellType::quadrilateral, 2}),
                         name);
