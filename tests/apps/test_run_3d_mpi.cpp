// `warpfem run` on polyhedra under MPI: two ranks give the serial solution, for
// Poisson on hexahedra and on TetGen's tetrahedra and for elasticity.

#include <gtest/gtest.h>

#include <variant>

#include "apps/run.hpp"

using namespace warpfem;

namespace {

template <class Config>
void expect_parallel_equals_serial(Config cfg, const std::string& name) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 2) << "run this test with mpiexec -n 2";
  cfg.verbosity = "warning";
  cfg.output.directory = "output/test_run_3d_mpi";
  cfg.output.name = name;
  const auto parallel = apps::run(cfg, MPI_COMM_WORLD, {.write_output = true, .gather_solution = true});
  const auto serial = apps::run(cfg, MPI_COMM_SELF, {.write_output = false, .gather_solution = true});
  ASSERT_EQ(parallel.solution.size(), serial.solution.size()) << name;
  ASSERT_GT(serial.solution.size(), 0) << name;
  EXPECT_LT((parallel.solution - serial.solution).template lpNorm<Eigen::Infinity>(),
            1e-8 * serial.solution.template lpNorm<Eigen::Infinity>())
      << name;
  EXPECT_EQ(parallel.h, serial.h) << name;
  EXPECT_EQ(parallel.output_file.substr(parallel.output_file.size() - 4), name == "bar" ? ".pvd" : "pvtu");
}

}  // namespace

TEST(MpiRun3d, PoissonOnHexahedraEqualsSerial) {
  auto cfg = std::get<io::PoissonRunConfig<3>>(io::load_config("examples/poisson_cube.json"));
  cfg.mesh.refinements = 1;
  cfg.solver.linear.rtol = 1e-12;
  expect_parallel_equals_serial(cfg, "cube");
}

TEST(MpiRun3d, PoissonOnTetrahedraEqualsSerial) {
  auto cfg = std::get<io::PoissonRunConfig<3>>(io::load_config("examples/poisson_polyhedron.json"));
  cfg.mesh.refinements = 1;
  cfg.solver.linear.rtol = 1e-12;
  expect_parallel_equals_serial(cfg, "prism");
}

TEST(MpiRun3d, ElasticityEqualsSerial) {
  auto cfg = std::get<io::ElasticityRunConfig<3>>(io::load_config("examples/elasticity_bar_3d.json"));
  cfg.mesh.refinements = 0;
  cfg.load_stepping.steps = 2;
  expect_parallel_equals_serial(cfg, "bar");
}
