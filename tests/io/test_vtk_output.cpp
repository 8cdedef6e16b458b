// The written VTU is read back with VTK's own reader.

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <filesystem>

#include "apps/poisson_run.hpp"
#include "io/atomic_file.hpp"

using namespace warpfem;

namespace {
io::RunConfig small_config(const std::string& dir) {
  const auto j = nlohmann::json::parse(R"json({
    "verbosity": "warning",
    "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
    "mesh": {"max_edge_length": 0.2},
    "problem": {"source": "0", "dirichlet": [{"value": "1 + x + 2*y"}]}
  })json");
  io::RunConfig cfg = io::parse_run_config(j, "test.json");
  cfg.output.directory = dir;
  return cfg;
}
}  // namespace

TEST(VtkOutput, VtuReadsBackWithPointsCellsAndSolution) {
  const std::string dir = "output/test_vtk_output";
  std::filesystem::remove_all(dir);
  const auto cfg = small_config(dir);
  const auto result = apps::run_poisson(cfg, MPI_COMM_SELF, {.write_output = true, .gather_solution = true});
  ASSERT_EQ(result.output_file, dir + "/solution.vtu");

  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(result.output_file.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  ASSERT_NE(grid, nullptr);
  EXPECT_EQ(grid->GetNumberOfCells(), result.num_cells);
  EXPECT_EQ(grid->GetNumberOfPoints(), result.num_dofs);  // P1 on the identity map: one point per vertex
  vtkDataArray* u = grid->GetPointData()->GetArray("u");
  ASSERT_NE(u, nullptr);
  ASSERT_NE(grid->GetPointData()->GetArray("det_Jf"), nullptr);
  ASSERT_NE(grid->GetCellData()->GetArray("rank"), nullptr);
  // Linear data is reproduced exactly by P1: the stored field equals 1 + x + 2y at every point.
  double worst = 0;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    double p[3];
    grid->GetPoint(i, p);
    worst = std::max(worst, std::abs(u->GetTuple1(i) - (1 + p[0] + 2 * p[1])));
  }
  EXPECT_LT(worst, 1e-8);
  // No temporary files are left behind.
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST(VtkOutput, QuadraticOutputUsesLagrangeCells) {
  const std::string dir = "output/test_vtk_output_p2";
  auto cfg = small_config(dir);
  cfg.poisson.order = 2;
  const auto result = apps::run_poisson(cfg, MPI_COMM_SELF);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(result.output_file.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  EXPECT_EQ(grid->GetNumberOfCells(), result.num_cells);
  EXPECT_EQ(grid->GetNumberOfPoints(), result.num_dofs);  // P2 nodes
  EXPECT_EQ(grid->GetCellType(0), VTK_LAGRANGE_TRIANGLE);
  EXPECT_EQ(grid->GetCell(0)->GetNumberOfPoints(), 6);
}

TEST(AtomicFile, FailedWriteLeavesOldFileIntact) {
  const std::string path = "output/test_atomic/result.txt";
  io::write_text_atomically(path, "old");
  EXPECT_THROW(io::write_atomically(path,
                                    [](const std::string& tmp) {
                                      io::write_text_atomically(tmp + ".unused", "");
                                      throw Error("simulated failure");
                                    }),
               Error);
  std::ifstream in(path);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "old");
}
