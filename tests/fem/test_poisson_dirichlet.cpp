// Dirichlet conditions are eliminated while the element matrices are added:
// the assembled system must be the one PETSc's MatZeroRowsColumns makes from
// the unconstrained system (unit rows and columns, b −= A_{:,D} g, b_D = g).

#include <gtest/gtest.h>
#include <petscmat.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "core/mesh/polygon_mesher.hpp"
#include "core/petsc/check.hpp"
#include "fem/physics/poisson.hpp"
#include "mapping/map.hpp"

using namespace warpfem;

TEST(PoissonDirichlet, AssemblyEliminatesAsZeroRowsColumnsDoes) {
  const Polygon l_shape = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L-shape");
  const warpfem::Mesh<2> mesh = warpfem::mesh_polygon(l_shape, {.max_edge_length = 0.3});
  const auto map = std::make_shared<mapping::IdentityMap<2>>();
  const std::vector<int> fixed_edges = {1, 2, 3};
  fem::PoissonData<2> free;
  free.source = [](const Point<2>& x, double) { return 1 + x.x() * x.y(); };
  free.neumann.push_back({.edges = {0}, .value = [](const Point<2>& x, double) { return x.x(); }});
  fem::PoissonData<2> constrained = free;
  constrained.dirichlet.push_back(
      {.edges = fixed_edges, .value = [](const Point<2>& x, double) { return std::sin(x.x()) + x.y(); }});

  for (int order : {1, 2}) {
    fem::PoissonProblem<2> with(MPI_COMM_SELF, mesh, map, order, 2 * order, constrained);
    fem::PoissonProblem<2> without(MPI_COMM_SELF, mesh, map, order, 2 * order, free);
    with.assemble();
    without.assemble();

    // The Dirichlet rows: the DOFs on facets of the fixed edges.
    std::vector<PetscInt> rows;
    for (Index f = 0; f < mesh.num_boundary_facets(); ++f)
      if (std::count(fixed_edges.begin(), fixed_edges.end(), mesh.facet_tags[static_cast<std::size_t>(f)]))
        for (Index d : with.dofs().facet_dofs(mesh, f)) rows.push_back(with.distribution().global(d));
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    ASSERT_GT(rows.size(), 10u) << "P" << order;
    PetscReal data_norm = 0;
    WARPFEM_PETSC_CHECK(VecNorm(with.solution(), NORM_INFINITY, &data_norm));
    ASSERT_GT(data_norm, 0.5) << "the Dirichlet data reach the solution vector, P" << order;

    WARPFEM_PETSC_CHECK(MatZeroRowsColumns(without.matrix(), static_cast<PetscInt>(rows.size()), rows.data(),
                                           1.0, with.solution(), without.rhs()));
    PetscReal a_norm = 0, b_norm = 0, diff = 0;
    WARPFEM_PETSC_CHECK(MatNorm(with.matrix(), NORM_FROBENIUS, &a_norm));
    WARPFEM_PETSC_CHECK(MatAXPY(without.matrix(), -1.0, with.matrix(), SAME_NONZERO_PATTERN));
    WARPFEM_PETSC_CHECK(MatNorm(without.matrix(), NORM_FROBENIUS, &diff));
    EXPECT_LE(diff, 1e-13 * a_norm) << "P" << order;
    WARPFEM_PETSC_CHECK(VecNorm(with.rhs(), NORM_2, &b_norm));
    WARPFEM_PETSC_CHECK(VecAXPY(without.rhs(), -1.0, with.rhs()));
    WARPFEM_PETSC_CHECK(VecNorm(without.rhs(), NORM_2, &diff));
    EXPECT_LE(diff, 1e-13 * b_norm) << "P" << order;
    PetscBool symmetric = PETSC_FALSE;
    WARPFEM_PETSC_CHECK(MatIsSymmetric(with.matrix(), 1e-12 * a_norm, &symmetric));
    EXPECT_TRUE(symmetric) << "P" << order;
  }
}
