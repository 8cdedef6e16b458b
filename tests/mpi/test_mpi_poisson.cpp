// Run under mpiexec -n 2: the distributed solve equals the serial one.

#include <gtest/gtest.h>

#include "apps/poisson_run.hpp"

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
  const auto parallel =
      apps::run_poisson(cfg, MPI_COMM_WORLD, {.write_output = true, .gather_solution = true});
  const auto serial = apps::run_poisson(cfg, MPI_COMM_SELF, {.write_output = false, .gather_solution = true});
  ASSERT_EQ(parallel.solution.size(), serial.solution.size());
  const double diff = (parallel.solution - serial.solution).lpNorm<Eigen::Infinity>();
  const double scale = serial.solution.lpNorm<Eigen::Infinity>();
  EXPECT_LT(diff, 1e-9 * scale) << "max difference " << diff;
  EXPECT_NEAR(parallel.area, serial.area, 1e-12);
  EXPECT_EQ(parallel.output_file, "output/test_mpi/p" + std::to_string(GetParam()) + ".pvtu");
}

INSTANTIATE_TEST_SUITE_P(Orders, MpiPoisson, ::testing::Values(1, 2));
