// The run recipe: one config loader and one function for every physics.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <variant>

#include "apps/run.hpp"
#include "core/error.hpp"

using namespace warpfem;
namespace fs = std::filesystem;

namespace {

const char* kPoisson = R"json({
  "verbosity": "warning",
  "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
  "mesh": {"type": "structured", "cells": [4, 4], "refinements": 1},
  "problem": {"source": "0", "dirichlet": [{"value": "1 + x + 2*y"}]},
  "output": {"directory": "poisson"}
})json";

const char* kElasticity = R"json({
  "verbosity": "warning",
  "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
  "mesh": {"type": "structured", "cells": [4, 4]},
  "problem": {"type": "elasticity", "order": 1,
              "material": {"model": "neo_hookean", "E": 1000, "nu": 0.3},
              "dirichlet": [{"edges": [0], "displacement": [0, 0]}, {"edges": [2], "displacement": [0, -0.1]}]},
  "load_stepping": {"steps": 2},
  "output": {"directory": "elasticity", "name": "block"}
})json";

io::Config load(const std::string& name, const std::string& text) {
  fs::create_directories("output/test_run");
  const std::string path = "output/test_run/" + name;
  std::ofstream(path) << text;
  return io::load_config(path);
}

}  // namespace

TEST(RunRecipe, ProblemTypeChoosesTheConfig) {
  EXPECT_TRUE(std::holds_alternative<io::RunConfig>(load("poisson.json", kPoisson)));
  EXPECT_TRUE(std::holds_alternative<io::ElasticityConfig>(load("elasticity.json", kElasticity)));
  try {
    load("bad_type.json",
         R"({"map": {"type": "identity", "source": [[0,0],[1,0],[0,1]]}, "problem": {"type": 3}})");
    FAIL() << "a non-string problem type was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/problem/type"), std::string::npos) << e.what();
  }
}

TEST(RunRecipe, SameStepsForPoissonAndElasticity) {
  // Both physics go through the same map, mesh and output steps: the same 8x8 grid
  // of the square, one unknown per node for Poisson and two for elasticity.
  fs::remove_all("output/test_run/poisson");
  fs::remove_all("output/test_run/elasticity");
  const apps::RunResult poisson = apps::run(load("poisson.json", kPoisson), MPI_COMM_SELF);
  EXPECT_EQ(poisson.num_cells, 64);
  EXPECT_EQ(poisson.num_dofs, 81);
  EXPECT_NEAR(poisson.h, 0.125, 1e-12);  // quadrilaterals of the 8x8 grid
  EXPECT_LT(poisson.solve.residual_norm, 1e-6);
  // A relative output directory starts at the config's directory.
  EXPECT_TRUE(fs::equivalent(fs::path(poisson.output_file).parent_path(), "output/test_run/poisson"));
  EXPECT_EQ(fs::path(poisson.output_file).filename(), "solution.vtu") << "one file under the output name";
  EXPECT_EQ(poisson.vtk_files.size(), 1u);
  EXPECT_TRUE(fs::exists(poisson.output_file));

  auto cfg = std::get<io::ElasticityConfig>(load("elasticity.json", kElasticity));
  cfg.mesh.refinements = 1;
  const apps::RunResult elasticity = apps::run(cfg, MPI_COMM_SELF, {.gather_solution = true});
  EXPECT_EQ(elasticity.num_cells, 64);
  EXPECT_EQ(elasticity.num_dofs, 2 * 81);
  EXPECT_EQ(elasticity.solution.size(), 2 * 81);
  EXPECT_NEAR(elasticity.h, poisson.h, 1e-12);
  EXPECT_EQ(elasticity.load_steps.size(), 2u);
  EXPECT_GT(elasticity.min_det_F, 0.5);
  EXPECT_TRUE(fs::equivalent(fs::path(elasticity.output_file).parent_path(), "output/test_run/elasticity"));
  EXPECT_EQ(fs::path(elasticity.output_file).filename(), "block.pvd") << "a series: the PVD index";
  EXPECT_EQ(elasticity.vtk_files.size(), 3u) << "initial state and both load steps";
  for (const auto& f : elasticity.vtk_files) EXPECT_TRUE(fs::exists(f)) << f;
}
