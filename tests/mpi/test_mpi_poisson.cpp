// Run under mpiexec -n 2: the distributed solve equals the serial one.

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPUnstructuredGridReader.h>

#include <cmath>
#include <ostream>
#include <string>

#include "apps/run.hpp"
#include "core/mesh/structured_mesher.hpp"
#include "core/mesh/uniform_refinement.hpp"
#include "core/petsc/check.hpp"
#include "fem/physics/poisson.hpp"
#include "fem/postprocessing/reference_error.hpp"
#include "io/config.hpp"
#include "mapping/make_map.hpp"

using namespace warpfem;

namespace {
io::RunConfig config(int order) {
  io::RunConfig cfg = io::parse_run_config(nlohmann::json::parse(R"json({
    "verbosity": "warning",
    "map": {"source": [[0,0],[2,0],[2,1],[1,1],[1,2],[0,2]]},
    "mesh": {"max_edge_length": 0.15, "refinements": 1},
    "problem": {"source": "1 + x*y", "dirichlet": [{"edges": [0, 1, 2], "value": "x"}],
                "neumann": [{"edges": [3, 4, 5], "value": "0.5"}]},
    "solver": {"rtol": 1e-12}
  })json"),
                                           "mpi_test.json");
  cfg.poisson.order = order;
  cfg.output.directory = "output/test_mpi";
  cfg.output.name = "p" + std::to_string(order);
  return cfg;
}
}  // namespace

class MpiPoisson : public ::testing::TestWithParam<int> {};

TEST_P(MpiPoisson, TwoRanksEqualSerial) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const auto cfg = config(GetParam());
  const auto parallel = apps::run(cfg, MPI_COMM_WORLD, {.write_output = true, .gather_solution = true});
  const auto serial = apps::run(cfg, MPI_COMM_SELF, {.write_output = false, .gather_solution = true});
  ASSERT_EQ(parallel.solution.size(), serial.solution.size());
  const double diff = (parallel.solution - serial.solution).lpNorm<Eigen::Infinity>();
  const double scale = serial.solution.lpNorm<Eigen::Infinity>();
  EXPECT_LT(diff, 1e-9 * scale) << "max difference " << diff;
  EXPECT_NEAR(parallel.area, serial.area, 1e-12);
  EXPECT_EQ(parallel.output_file, "output/test_mpi/p" + std::to_string(GetParam()) + ".pvtu");
  // Read back: every cell carries the rank that wrote it, one byte each.
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    vtkNew<vtkXMLPUnstructuredGridReader> reader;
    reader->SetFileName(parallel.output_file.c_str());
    reader->Update();
    vtkDataArray* ranks = reader->GetOutput()->GetCellData()->GetArray("rank");
    ASSERT_NE(ranks, nullptr);
    EXPECT_EQ(ranks->GetDataType(), VTK_UNSIGNED_CHAR);
    EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), parallel.num_cells);
    Index on_rank1 = 0;
    for (vtkIdType c = 0; c < ranks->GetNumberOfTuples(); ++c) {
      const double r = ranks->GetTuple1(c);
      ASSERT_TRUE(r == 0 || r == 1) << "cell " << c << ": rank " << r;
      on_rank1 += r == 1;
    }
    EXPECT_GT(on_rank1, 0);
    EXPECT_LT(on_rank1, parallel.num_cells);
  }
}

namespace {
/// y = A x and b of a Poisson problem on `comm`, at every mesh DOF (the PETSc
/// numbering differs between one and two ranks), for x_d = sin(3 x) cos(2 y)
/// at DOF node d. Assembled twice: the second pass must give the same values.
std::pair<VectorX, VectorX> operator_and_load(MPI_Comm comm, const warpfem::Mesh<2>& mesh,
                                              const mapping::MapPtr<2>& map, int order) {
  fem::PoissonData<2> data;
  data.source = [](const Point<2>& x, double) { return 1 + x.x() * x.y(); };
  data.dirichlet.push_back({.edges = {0, 1}, .value = [](const Point<2>& x, double) { return x.x(); }});
  fem::PoissonProblem<2> problem(comm, mesh, map, order, 2 * order + 2, data);
  problem.assemble();
  problem.assemble();
  const fem::DofDistribution<2>& dist = problem.distribution();
  petsc::Vector x = dist.create_vector(), y = dist.create_vector();
  const Points<2>& nodes = problem.dofs().dof_points();
  for (Index d = 0; d < problem.dofs().num_dofs(); ++d)
    if (dist.owns(d))
      WARPFEM_PETSC_CHECK(VecSetValue(x.get(), dist.global(d),
                                      std::sin(3 * nodes(d, 0)) * std::cos(2 * nodes(d, 1)), INSERT_VALUES));
  WARPFEM_PETSC_CHECK(VecAssemblyBegin(x.get()));
  WARPFEM_PETSC_CHECK(VecAssemblyEnd(x.get()));
  WARPFEM_PETSC_CHECK(MatMult(problem.matrix(), x.get(), y.get()));
  return {dist.gather_all(y.get()), dist.gather_all(problem.rhs())};
}
}  // namespace

// The distributed matrix and load vector equal the serial ones entry by entry
// (through their action on a smooth vector): the MPI assembly writes the
// owned rows into PETSc's diagonal and off-diagonal blocks itself and sends
// the other rows' entries; a warped map, P1 and P2.
TEST_P(MpiPoisson, TwoRankOperatorEqualsSerial) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  mapping::MapSpec spec;
  spec.type = "composite_mean_value";
  spec.source = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}}, "pentagon");
  spec.target = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0.5, 0.75}, {0, 1}}, "bent pentagon");
  const mapping::MapPtr<2> map = mapping::make_map(spec);
  const warpfem::Mesh<2> mesh =
      warpfem::refine_uniformly(warpfem::structured_mesh(*spec.source, 6, 6, warpfem::CellType::triangle))
          .mesh;
  const auto [y_parallel, b_parallel] = operator_and_load(MPI_COMM_WORLD, mesh, map, GetParam());
  const auto [y_serial, b_serial] = operator_and_load(MPI_COMM_SELF, mesh, map, GetParam());
  ASSERT_EQ(y_parallel.size(), y_serial.size());
  EXPECT_LT((y_parallel - y_serial).lpNorm<Eigen::Infinity>(), 1e-12 * y_serial.lpNorm<Eigen::Infinity>());
  EXPECT_LT((b_parallel - b_serial).lpNorm<Eigen::Infinity>(), 1e-12 * b_serial.lpNorm<Eigen::Infinity>());
}

INSTANTIATE_TEST_SUITE_P(Orders, MpiPoisson, ::testing::Values(1, 2));

// Enough refinements that the multigrid hierarchy's finest levels are built
// only around each rank's cells (fem/partial_refinement.hpp): the app's
// solution, h, measure and curved (order-2) output are the serial ones, for
// triangles, quadrilaterals and hexahedra.
struct PartialCase {
  const char* name;
  int dim;
  const char* map;      // the config's "map" member
  const char* mesh;     // its "mesh" member
  const char* problem;  // its "problem" member
  // Printed by name (not as raw bytes, which include the padding).
  friend void PrintTo(const PartialCase& c, std::ostream* os) { *os << c.name; }
};

class MpiPartialLevels : public ::testing::TestWithParam<PartialCase> {};

TEST_P(MpiPartialLevels, GiveTheSerialRun) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const PartialCase& c = GetParam();
  const nlohmann::json json = nlohmann::json::parse(
      std::string(R"({"verbosity": "warning", "map": )") + c.map + R"(, "mesh": )" + c.mesh +
      R"(, "problem": )" + c.problem +
      R"(, "solver": {"rtol": 1e-12}, "output": {"vtk_order": 2, "directory": "output/test_mpi", "name": "partial_)" +
      c.name + R"("}})");
  const io::Config cfg = c.dim == 2 ? io::Config(io::parse_run_config(json, "mpi_partial_test.json"))
                                    : io::Config(io::parse_poisson_config<3>(json, "mpi_partial_test.json"));
  const auto parallel = apps::run(cfg, MPI_COMM_WORLD, {.write_output = true, .gather_solution = true});
  const auto serial = apps::run(cfg, MPI_COMM_SELF, {.write_output = false, .gather_solution = true});
  EXPECT_GE(parallel.partial_levels, 1) << "the case no longer builds partial levels";
  EXPECT_EQ(serial.partial_levels, 0);
  ASSERT_EQ(parallel.solution.size(), serial.solution.size());
  EXPECT_LT((parallel.solution - serial.solution).lpNorm<Eigen::Infinity>(),
            1e-9 * serial.solution.lpNorm<Eigen::Infinity>());
  EXPECT_EQ(parallel.h, serial.h);
  EXPECT_NEAR(parallel.area, serial.area, 1e-12);
  EXPECT_EQ(parallel.output_file, "output/test_mpi/partial_" + std::string(c.name) + ".pvtu");
}

constexpr const char* kLMap =
    R"({"type": "composite_mean_value", "source": [[0,0],[2,0],[2,1],[1,1],[1,2],[0,2]],
                                  "target": [[0,0],[2,0],[2.2,1.1],[1,1],[1,2],[-0.1,2.1]]})";
constexpr const char* kLProblem = R"({"source": "1 + x*y", "dirichlet": [{"edges": [0, 1, 2], "value": "x"}],
                                      "neumann": [{"edges": [3, 4, 5], "value": "0.5"}]})";

INSTANTIATE_TEST_SUITE_P(
    Cells, MpiPartialLevels,
    ::testing::Values(
        PartialCase{"triangles", 2, kLMap, R"({"max_edge_length": 0.4, "refinements": 5})", kLProblem},
        PartialCase{"quadrilaterals", 2, kLMap,
                    R"({"type": "quad_split", "max_edge_length": 0.5, "refinements": 4})", kLProblem},
        // The unit cube's surface under the identity, 2³ hexahedra refined 4 times (35,937 DOFs).
        PartialCase{"hexahedra", 3, R"({"type": "identity", "source": {
                      "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],
                      "triangles": [[0,4,7],[0,7,3],[1,2,6],[1,6,5],[0,1,5],[0,5,4],
                                    [3,7,6],[3,6,2],[0,2,1],[0,3,2],[4,5,6],[4,6,7]]}})",
                    R"({"type": "structured", "cell_type": "hexahedron", "cells": 2, "refinements": 4})",
                    R"({"source": "1 + x*y*z", "dirichlet": [{"faces": [0, 1, 2, 3, 4], "value": "x + z"}],
                        "neumann": [{"faces": [5], "value": "0.5"}]})"}),
    [](const auto& info) { return std::string(info.param.name); });

// Errors against a reference solution locate every quadrature point of one
// problem in the other's mesh, rank by rank. A point outside the reference
// mesh is an error on every rank: here the reference square's corner (1, 1)
// is moved inward, so only the rank that owns the cells at that corner finds
// points outside, and without the agreement the other rank would wait forever
// in the final sum.
TEST(MpiPoisson, APointOutsideTheReferenceMeshOnOneRankEndsEveryRank) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, "square");
  const warpfem::Mesh<2> mesh = structured_mesh(square, 32, 32, CellType::triangle);
  warpfem::Mesh<2> shrunk = structured_mesh(square, 16, 16, CellType::triangle);
  for (Index v = 0; v < shrunk.num_vertices(); ++v)  // its cells stay positive for either diagonal
    if (shrunk.vertices(v, 0) > 1 - 1e-12 && shrunk.vertices(v, 1) > 1 - 1e-12)
      shrunk.vertices.row(v) = Point<2>(0.97, 0.97).transpose();
  const auto map = mapping::make_map(mapping::MapSpec{});  // identity
  fem::PoissonData<2> data;
  data.source = [](const Point<2>&, double) { return 1.0; };
  data.dirichlet.push_back({.edges = {0, 1, 2, 3}, .value = [](const Point<2>&, double) { return 0.0; }});
  fem::PoissonProblem<2> coarse(MPI_COMM_WORLD, mesh, map, 1, 2, data);
  fem::PoissonProblem<2> reference(MPI_COMM_WORLD, shrunk, map, 1, 2, data);
  for (fem::PoissonProblem<2>* p : {&coarse, &reference}) {
    p->assemble();
    p->solve({});
  }
  try {
    (void)fem::error_against_reference(coarse, reference);
    ADD_FAILURE() << "a point outside the reference mesh was not reported";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.message()).find("outside the reference solution's mesh"), std::string::npos)
        << e.message();
  }
}
