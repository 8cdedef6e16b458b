// DofDistribution<3> of P1/P2 on Kuhn tetrahedra and Q1/Q2 on hexahedra, on
// one rank and (as test_mpi_dof_distribution) on two: the parallel numbering
// is the serial mesh numbering up to a permutation (a value written at each
// DOF's PETSc index comes back at that DOF), every DOF and cell is owned once,
// and each row of the sparsity pattern couples the same DOFs as serially.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

#include "core/error.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/petsc/check.hpp"
#include "fem/dofs/cell_partition.hpp"
#include "fem/dofs/dof_distribution.hpp"

using namespace warpfem;

namespace {

struct Case {
  CellType type;
  int order;
};

class DofDistribution3d : public ::testing::TestWithParam<Case> {};

/// A value that tells the DOFs apart by their points.
double tag(const Points<3>& x, Index d) {
  return x(d, 0) + 3.0 * x(d, 1) + 17.0 * x(d, 2);
}

}  // namespace

TEST_P(DofDistribution3d, ParallelNumberingIsTheSerialOneUpToPermutation) {
  const Mesh<3> mesh = structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), {3, 4, 2}, GetParam().type);
  const fem::DofMap<3> dofs(mesh, fem::LagrangeElement<3>(mesh.cell_type, GetParam().order));
  const fem::DofDistribution<3> dist(MPI_COMM_WORLD, mesh, dofs);
  const fem::DofDistribution<3> serial(MPI_COMM_SELF, mesh, dofs);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(dist.num_global(), dofs.num_dofs());

  // Every DOF owned by one rank, every cell by one rank.
  std::vector<int> owned(static_cast<std::size_t>(dofs.num_dofs()), 0);
  for (Index d = 0; d < dofs.num_dofs(); ++d) owned[static_cast<std::size_t>(d)] = dist.owns(d) ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, owned.data(), static_cast<int>(owned.size()), MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(std::count(owned.begin(), owned.end(), 1), dofs.num_dofs());
  std::vector<int> cell_count(static_cast<std::size_t>(mesh.num_cells()), 0);
  for (const Index c : dist.local_cells()) ++cell_count[static_cast<std::size_t>(c)];
  MPI_Allreduce(MPI_IN_PLACE, cell_count.data(), static_cast<int>(cell_count.size()), MPI_INT, MPI_SUM,
                MPI_COMM_WORLD);
  EXPECT_EQ(std::count(cell_count.begin(), cell_count.end(), 1), mesh.num_cells());
  if (size > 1) {
    EXPECT_LT(dist.local_cells().size(), static_cast<std::size_t>(mesh.num_cells()));
  }
  // Owned DOFs have their PETSc indices in the rank's range.
  for (Index d = 0; d < dofs.num_dofs(); ++d)
    if (dist.owns(d)) {
      EXPECT_GE(dist.global(d), dist.owned_begin());
      EXPECT_LT(dist.global(d), dist.owned_end());
    }

  // Written at each owned DOF's PETSc index, gathered back by mesh DOF.
  petsc::Vector v = dist.create_vector();
  for (Index d = 0; d < dofs.num_dofs(); ++d)
    if (dist.owns(d))
      WARPFEM_PETSC_CHECK(VecSetValue(v.get(), dist.global(d), tag(dofs.dof_points(), d), INSERT_VALUES));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(v.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(v.get()));
  const VectorX all = dist.gather_all(v.get());
  ASSERT_EQ(all.size(), dofs.num_dofs());
  for (Index d = 0; d < dofs.num_dofs(); ++d) ASSERT_EQ(all(d), tag(dofs.dof_points(), d)) << "DOF " << d;
  // Ghosts: the relevant values are those of the DOFs they name.
  const VectorX relevant = dist.gather_relevant(v.get());
  for (std::size_t i = 0; i < dist.relevant_dofs().size(); ++i)
    ASSERT_EQ(relevant(static_cast<Index>(i)), tag(dofs.dof_points(), dist.relevant_dofs()[i]));

  // Sparsity: owned row of DOF d has the serial row length of d (the same
  // coupled DOFs, numbered differently), and couples d's serial neighbours.
  std::vector<PetscInt> row_ptr, cols, serial_ptr, serial_cols;
  dist.sparsity(mesh, dofs, row_ptr, cols);
  serial.sparsity(mesh, dofs, serial_ptr, serial_cols);
  std::vector<Index> dof_of_serial(static_cast<std::size_t>(dofs.num_dofs()));
  for (Index d = 0; d < dofs.num_dofs(); ++d) dof_of_serial[static_cast<std::size_t>(serial.global(d))] = d;
  std::vector<PetscInt> global_of(static_cast<std::size_t>(dofs.num_dofs()));
  for (Index d = 0; d < dofs.num_dofs(); ++d) global_of[static_cast<std::size_t>(d)] = dist.global(d);
  for (Index d = 0; d < dofs.num_dofs(); ++d) {
    if (!dist.owns(d)) continue;
    const PetscInt r = dist.global(d) - dist.owned_begin(), s = serial.global(d);
    std::vector<PetscInt> mapped;
    for (PetscInt k = serial_ptr[s]; k < serial_ptr[s + 1]; ++k)
      mapped.push_back(
          global_of[static_cast<std::size_t>(dof_of_serial[static_cast<std::size_t>(serial_cols[k])])]);
    std::sort(mapped.begin(), mapped.end());
    const std::vector<PetscInt> row(cols.begin() + row_ptr[r], cols.begin() + row_ptr[r + 1]);
    ASSERT_EQ(row, mapped) << "DOF " << d;
  }
}

TEST_P(DofDistribution3d, SparsityRowsAreTheDofsSharingACellAndSplitRowsTheSame) {
  const Mesh<3> mesh = structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), {3, 2, 4}, GetParam().type);
  const fem::DofMap<3> dofs(mesh, fem::LagrangeElement<3>(mesh.cell_type, GetParam().order));
  const fem::DofDistribution<3> dist(MPI_COMM_WORLD, mesh, dofs);
  // By brute force: the PETSc indices of the DOFs sharing a cell with each DOF.
  std::vector<std::vector<PetscInt>> expected(static_cast<std::size_t>(dofs.num_dofs()));
  const IndexTable& cd = dofs.cell_dofs();
  for (Index c = 0; c < mesh.num_cells(); ++c)
    for (Index a = 0; a < cd.cols(); ++a)
      for (Index b = 0; b < cd.cols(); ++b)
        expected[static_cast<std::size_t>(cd(c, a))].push_back(dist.global(cd(c, b)));
  for (auto& row : expected) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  std::vector<PetscInt> row_ptr, cols, own_ptr, own_cols, off_ptr, off_cols;
  dist.sparsity(mesh, dofs, row_ptr, cols);
  dist.sparsity_split(mesh, dofs, own_ptr, own_cols, off_ptr, off_cols);
  ASSERT_EQ(static_cast<PetscInt>(row_ptr.size()), dist.num_owned() + 1);
  for (Index d = 0; d < dofs.num_dofs(); ++d) {
    if (!dist.owns(d)) continue;
    const PetscInt r = dist.global(d) - dist.owned_begin();
    const std::vector<PetscInt> row(cols.begin() + row_ptr[r], cols.begin() + row_ptr[r + 1]);
    ASSERT_EQ(row, expected[static_cast<std::size_t>(d)]) << "DOF " << d;
    // Split: the own columns as sorted local indices, the others sorted and global.
    std::vector<PetscInt> own(own_cols.begin() + own_ptr[r], own_cols.begin() + own_ptr[r + 1]);
    const std::vector<PetscInt> off(off_cols.begin() + off_ptr[r], off_cols.begin() + off_ptr[r + 1]);
    EXPECT_TRUE(std::is_sorted(own.begin(), own.end()) && std::is_sorted(off.begin(), off.end()));
    for (PetscInt& k : own) {
      EXPECT_TRUE(k >= 0 && k < dist.num_owned());
      k += dist.owned_begin();
    }
    for (const PetscInt k : off) EXPECT_TRUE(k < dist.owned_begin() || k >= dist.owned_end());
    own.insert(own.end(), off.begin(), off.end());
    std::sort(own.begin(), own.end());
    ASSERT_EQ(own, row) << "DOF " << d;
  }
}

TEST(DofDistribution3d, Partitions3dMeshesAndRefusesBlocksOfAnotherMesh) {
  const Mesh<3> mesh =
      structured_box_mesh(Point<3>(0, 0, 0), Point<3>(1, 1, 1), {4, 4, 4}, CellType::hexahedron);
  const std::vector<int> owner = fem::partition_cells(mesh, 4);
  // Equal parts, each spatially compact: a Morton part of a 4³ grid is a 2³ block.
  for (int p = 0; p < 4; ++p) {
    EXPECT_EQ(std::count(owner.begin(), owner.end(), p), 16);
    Point<3> lo = Point<3>::Constant(1e9), hi = Point<3>::Constant(-1e9);
    for (Index c = 0; c < mesh.num_cells(); ++c)
      if (owner[static_cast<std::size_t>(c)] == p)
        for (int k = 0; k < 8; ++k) {
          lo = lo.cwiseMin(mesh.vertex(mesh.cells(c, k)));
          hi = hi.cwiseMax(mesh.vertex(mesh.cells(c, k)));
        }
    EXPECT_NEAR((hi - lo).prod(), 0.5 * 0.5 * 1.0, 1e-12) << "part " << p;
  }
  const fem::DofMap<3> dofs(mesh, fem::LagrangeElement<3>(mesh.cell_type, 1));
  fem::NestedBlocks blocks;  // no blocks: not this mesh's 64 cells
  EXPECT_THROW(fem::DofDistribution<3>(MPI_COMM_SELF, mesh, dofs, blocks), warpfem::Error);
}

INSTANTIATE_TEST_SUITE_P(Elements, DofDistribution3d,
                         ::testing::Values(Case{CellType::tetrahedron, 1}, Case{CellType::tetrahedron, 2},
                                           Case{CellType::hexahedron, 1}, Case{CellType::hexahedron, 2}),
                         [](const auto& info) {
                           return to_string(info.param.type) + "_order" + std::to_string(info.param.order);
                         });
