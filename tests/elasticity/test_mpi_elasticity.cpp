// Run under mpiexec -n 2: distributed elasticity solves equal the serial ones.

#include <gtest/gtest.h>

#include "apps/run.hpp"

using namespace warpfem;

namespace {

io::ElasticityConfig config(const std::string& analysis) {
  nlohmann::json json = nlohmann::json::parse(R"json({
    "verbosity": "warning",
    "map": {"type": "barycentric", "source": [[0,0],[2,0],[2,1],[0,1]], "target": [[0,0],[2,0.2],[2.1,1.1],[0,1]]},
    "mesh": {"type": "delaunay", "max_edge_length": 0.2},
    "problem": {"type": "elasticity", "order": 2,
                "material": {"model": "neo_hookean", "E": 100, "nu": 0.3, "density": 2},
                "gravity": [0, -1],
                "dirichlet": [{"edges": [3], "displacement": [0, 0]}],
                "neumann": [{"edges": [1], "traction": [0, "-1 - y"]}]},
    "output": {"directory": "output/test_mpi_elasticity"}
  })json");
  // "quasi_static_multigrid": one refinement of a coarser mesh and pc_type "mg":
  // Newton's linear solves use the two-level hierarchy on the app's
  // nested_partitions() cells, and so does the output's nodal projection. (With
  // this few cells each level is still cut on its own Morton curve; inherited
  // levels are checked in test_mpi_multigrid.)
  const bool multigrid = analysis == "quasi_static_multigrid";
  json["problem"]["analysis"] = multigrid ? "quasi_static" : analysis;
  json["output"]["name"] = analysis;
  if (multigrid) {
    json["mesh"] = {{"type", "delaunay"}, {"max_edge_length", 0.3}, {"refinements", 1}};
    json["solver"] = {{"pc_type", "mg"}};
  }
  if (analysis == "transient")
    json["time"] = {{"step", 0.02}, {"end", 0.1}};
  else
    json["load_stepping"] = {{"steps", 2}};
  return io::parse_elasticity_config(json, "mpi_test.json");
}

class MpiElasticity : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(MpiElasticity, TwoRanksEqualSerial) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  const auto cfg = config(GetParam());
  const auto parallel = apps::run(cfg, MPI_COMM_WORLD, {.write_output = true, .gather_solution = true});
  const auto serial = apps::run(cfg, MPI_COMM_SELF, {.write_output = false, .gather_solution = true});
  ASSERT_EQ(parallel.solution.size(), serial.solution.size());
  const double scale = serial.solution.lpNorm<Eigen::Infinity>();
  EXPECT_GT(scale, 1e-3);
  const double diff = (parallel.solution - serial.solution).lpNorm<Eigen::Infinity>();
  EXPECT_LT(diff, 1e-8 * scale) << "max difference " << diff;
  EXPECT_EQ(parallel.newton_iterations, serial.newton_iterations);
  EXPECT_NE(parallel.vtk_files.back().find(".pvtu"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Analyses, MpiElasticity,
                         ::testing::Values("quasi_static", "transient", "quasi_static_multigrid"));
