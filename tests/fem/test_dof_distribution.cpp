// The matrix sparsity pattern: every owned row lists, sorted and without
// duplicates, exactly the DOFs that share a cell with the row's DOF, also when
// split into PETSc's diagonal and off-diagonal blocks (on one
// rank, and on two as test_mpi_dof_distribution: the other rank's columns on
// both sides of the own range included).

#include <gtest/gtest.h>

#include <set>

#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "fem/dofs/dof_distribution.hpp"
#include "fem/dofs/dof_map.hpp"
#include "fem/reference/lagrange_element.hpp"

using namespace warpfem;

namespace {

/// On every rank of MPI_COMM_WORLD (this file also runs under mpiexec -n 2 as
/// test_mpi_dof_distribution): every owned row is the brute-force coupling.
void expect_sparsity_is_the_cell_coupling(const warpfem::Mesh<2>& mesh, int order) {
  const fem::DofMap<2> dofs(mesh, fem::LagrangeElement<2>(mesh.cell_type, order));
  const fem::DofDistribution<2> dist(MPI_COMM_WORLD, mesh, dofs);
  std::vector<PetscInt> row_ptr, cols;
  dist.sparsity(mesh, dofs, row_ptr, cols);
  // Brute force: the global DOFs coupled through some cell with an owned DOF.
  std::vector<std::set<PetscInt>> expected(static_cast<std::size_t>(dist.num_owned()));
  const auto& cd = dofs.cell_dofs();
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (Index a = 0; a < cd.cols(); ++a)
      if (dist.owns(cd(c, a)))
        for (Index b = 0; b < cd.cols(); ++b)
          expected[static_cast<std::size_t>(dist.global(cd(c, a)) - dist.owned_begin())].insert(
              dist.global(cd(c, b)));
  ASSERT_EQ(static_cast<PetscInt>(row_ptr.size()), dist.num_owned() + 1);
  bool foreign_below = false, foreign_above = false;
  for (std::size_t r = 0; r + 1 < row_ptr.size(); ++r) {
    const std::vector<PetscInt> row(cols.begin() + row_ptr[r], cols.begin() + row_ptr[r + 1]);
    const std::vector<PetscInt> want(expected[r].begin(), expected[r].end());  // sorted, unique
    ASSERT_EQ(row, want) << "owned row " << r << ", order " << order;
    for (const PetscInt c : row) {
      foreign_below |= c < dist.owned_begin();
      foreign_above |= c >= dist.owned_end();
    }
  }
  // The split form: the same rows, own columns local, the others global.
  std::vector<PetscInt> own_ptr, own_cols, off_ptr, off_cols;
  dist.sparsity_split(mesh, dofs, own_ptr, own_cols, off_ptr, off_cols);
  ASSERT_EQ(own_ptr.size(), row_ptr.size());
  ASSERT_EQ(off_ptr.size(), row_ptr.size());
  for (std::size_t r = 0; r + 1 < row_ptr.size(); ++r) {
    std::vector<PetscInt> own, off;
    for (PetscInt k = row_ptr[r]; k < row_ptr[r + 1]; ++k)
      if (cols[k] >= dist.owned_begin() && cols[k] < dist.owned_end())
        own.push_back(cols[k] - dist.owned_begin());
      else
        off.push_back(cols[k]);
    ASSERT_EQ(std::vector<PetscInt>(own_cols.begin() + own_ptr[r], own_cols.begin() + own_ptr[r + 1]), own)
        << "owned row " << r;
    ASSERT_EQ(std::vector<PetscInt>(off_cols.begin() + off_ptr[r], off_cols.begin() + off_ptr[r + 1]), off)
        << "owned row " << r;
  }
  // On two ranks the rows along the interface hold the other rank's columns.
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 2) {
    EXPECT_TRUE(rank == 0 ? foreign_above : foreign_below) << "no interface on rank " << rank;
  }
}

}  // namespace

TEST(Sparsity, RowsAreTheSortedCellCouplingOfTriangles) {
  const Polygon l_shape = Polygon::checked({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, "L");
  const warpfem::Mesh<2> mesh =
      warpfem::refine_uniformly(warpfem::mesh_polygon(l_shape, {.max_edge_length = 0.4})).mesh;
  for (int order : {1, 2}) expect_sparsity_is_the_cell_coupling(mesh, order);
}

TEST(Sparsity, RowsAreTheSortedCellCouplingOfQuadrilaterals) {
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "square");
  const warpfem::Mesh<2> mesh =
      warpfem::split_into_quadrilaterals(warpfem::mesh_polygon(square, {.max_edge_length = 0.3}));
  for (int order : {1, 2}) expect_sparsity_is_the_cell_coupling(mesh, order);
}

TEST(DofDistribution, GivenCellOwnersAreCheckedAndUsed) {
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "square");
  const warpfem::Mesh<2> mesh = warpfem::mesh_polygon(square, {.max_edge_length = 0.3});
  const fem::DofMap<2> dofs(mesh, fem::LagrangeElement<2>(mesh.cell_type, 2));
  const std::vector<int> all_mine(static_cast<std::size_t>(mesh.num_cells()), 0);
  const fem::DofDistribution<2> given(MPI_COMM_SELF, mesh, dofs, all_mine), morton(MPI_COMM_SELF, mesh, dofs);
  EXPECT_EQ(given.local_cells(), morton.local_cells());
  EXPECT_EQ(given.num_owned(), dofs.num_dofs());
  // One owner too few, or a rank the communicator does not have.
  const std::vector<int> short_list(all_mine.begin(), all_mine.end() - 1);
  EXPECT_THROW(fem::DofDistribution<2>(MPI_COMM_SELF, mesh, dofs, short_list), warpfem::Error);
  std::vector<int> foreign = all_mine;
  foreign[3] = 1;
  EXPECT_THROW(fem::DofDistribution<2>(MPI_COMM_SELF, mesh, dofs, foreign), warpfem::Error);
}

TEST(DofDistribution, NumbersDofsByFirstUseInTheCells) {
  // PETSc's numbering follows the cells, not the DofMap's blocks (vertices,
  // then edges): cell c's DOFs not used by an earlier cell take the next indices.
  // P1/Q1 keep the mesh's vertex order, which is first use on refined meshes.
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "square");
  const warpfem::Mesh<2> triangles =
      warpfem::refine_uniformly(warpfem::mesh_polygon(square, {.max_edge_length = 0.3})).mesh;
  const warpfem::Mesh<2> quads =
      warpfem::refine_uniformly(
          warpfem::split_into_quadrilaterals(warpfem::mesh_polygon(square, {.max_edge_length = 0.3})))
          .mesh;
  for (const warpfem::Mesh<2>* mesh : {&triangles, &quads})
    for (int order : {1, 2}) {
      const fem::DofMap<2> dofs(*mesh, fem::LagrangeElement<2>(mesh->cell_type, order));
      const fem::DofDistribution<2> dist(MPI_COMM_SELF, *mesh, dofs);
      std::vector<char> seen(static_cast<std::size_t>(dofs.num_dofs()), 0);
      PetscInt next = 0;
      const auto& cd = dofs.cell_dofs();
      for (Index c = 0; c < mesh->num_cells(); ++c)
        for (Index k = 0; k < cd.cols(); ++k)
          if (!seen[static_cast<std::size_t>(cd(c, k))]) {
            seen[static_cast<std::size_t>(cd(c, k))] = 1;
            ASSERT_EQ(dist.global(cd(c, k)), next++) << "cell " << c << ", order " << order;
          }
      EXPECT_EQ(next, dofs.num_dofs());
    }
}

TEST(DofMap, FirstOrderDofsAreTheMeshVerticesWithoutACopy) {
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "square");
  const warpfem::Mesh<2> triangles = warpfem::mesh_polygon(square, {.max_edge_length = 0.3});
  const warpfem::Mesh<2> quads = warpfem::split_into_quadrilaterals(triangles);
  for (const warpfem::Mesh<2>* mesh : {&triangles, &quads}) {
    const fem::DofMap<2> p1(*mesh, fem::LagrangeElement<2>(mesh->cell_type, 1));
    EXPECT_EQ(p1.num_dofs(), mesh->num_vertices());
    EXPECT_EQ(&p1.cell_dofs(), &mesh->cells);  // documented: P1/Q1 refer to the mesh
    EXPECT_EQ(&p1.dof_points(), &mesh->vertices);
    // Order 2 numbers its own table: vertices first, then one DOF per edge.
    const fem::DofMap<2> p2(*mesh, fem::LagrangeElement<2>(mesh->cell_type, 2));
    EXPECT_EQ(p2.cell_dofs().leftCols(mesh->cells.cols()), mesh->cells);
    EXPECT_EQ(p2.dof_points().topRows(mesh->num_vertices()), mesh->vertices);
  }
}
