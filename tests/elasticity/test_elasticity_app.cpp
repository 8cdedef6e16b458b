// Elasticity configs, the PVD index and the `warpfem run` pipeline as users drive it.

#include <gtest/gtest.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLUtilities.h>

#include <filesystem>
#include <fstream>

#include "apps/run.hpp"
#include "io/pvd_writer.hpp"

using namespace warpfem;
namespace fs = std::filesystem;

namespace {

const char* kBlock = R"json({
  "verbosity": "warning",
  "map": {"type": "barycentric", "source": [[0,0],[1,0],[1,1],[0,1]], "target": [[0,0],[1.2,0],[1,1],[0.2,1]]},
  "mesh": {"type": "structured", "cells": [4, 4]},
  "problem": {"type": "elasticity", "order": 2,
              "material": {"model": "neo_hookean", "E": 1000, "nu": 0.3},
              "dirichlet": [{"edges": [0], "displacement": [0, 0]}, {"edges": [2], "displacement": [0, -0.3]}]},
  "load_stepping": {"steps": 2},
  "output": {"directory": "output/test_elasticity/block", "name": "block"}
})json";

io::ElasticityConfig parse(const std::string& text) {
  return io::parse_elasticity_config(nlohmann::json::parse(text, nullptr, true, true), "test.json");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

std::string with(const std::string& base, const std::string& from, const std::string& to) {
  std::string s = base;
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

}  // namespace

TEST(ElasticityConfig, ParsesTheBlockExample) {
  const auto cfg = parse(kBlock);
  EXPECT_EQ(cfg.problem.analysis, "quasi_static");
  EXPECT_EQ(cfg.problem.order, 2);
  EXPECT_NEAR(cfg.problem.material.mu, 1000 / 2.6, 1e-9);
  ASSERT_EQ(cfg.problem.dirichlet.size(), 2u);
  EXPECT_EQ(cfg.problem.dirichlet[1].edges, std::vector<int>{2});
  EXPECT_EQ(cfg.problem.dirichlet[1].value[1], "-0.29999999999999999");
  EXPECT_EQ(cfg.load_stepping.steps, 2);
  EXPECT_EQ(io::problem_type(nlohmann::json::parse(kBlock), "test.json"), "elasticity");
  EXPECT_EQ(io::problem_type(nlohmann::json::parse(R"({"map": {}})"), "test.json"), "poisson");
}

TEST(ElasticityConfig, NullLeavesADisplacementComponentFree) {
  const auto cfg = parse(with(kBlock, R"("displacement": [0, 0])", R"("displacement": [null, "0*x"])"));
  EXPECT_EQ(cfg.problem.dirichlet[0].value[0], "");
  const auto data = io::make_elasticity_data(cfg);
  EXPECT_FALSE(data.dirichlet[0].value[0]);
  EXPECT_TRUE(data.dirichlet[0].value[1]);
}

TEST(ElasticityConfig, ErrorsNameTheFieldAndHowToFixIt) {
  EXPECT_NE(error_of(with(kBlock, R"("steps": 2)", R"("step": 2)"))
                .find("/load_stepping/step: unknown key \"step\""),
            std::string::npos);
  EXPECT_NE(
      error_of(with(kBlock, R"("E": 1000)", R"("E": 1000, "mu": 3)")).find("either (E, nu) or (lambda, mu)"),
      std::string::npos);
  EXPECT_NE(error_of(with(kBlock, R"("nu": 0.3)", R"("nu": 0.5)")).find("/problem/material/nu"),
            std::string::npos);
  EXPECT_NE(error_of(with(kBlock, R"("load_stepping": {"steps": 2})", R"("time": {"end": 1})"))
                .find("/time: time stepping is for \"analysis\": \"transient\""),
            std::string::npos);
  EXPECT_NE(error_of(with(kBlock, R"("edges": [2])", R"("edges": [4])")).find("/problem/dirichlet/1/edges/0"),
            std::string::npos);
  EXPECT_NE(
      error_of(with(kBlock, R"([0, -0.3])", R"x([0, "sin("])x")).find("/problem/dirichlet/1/displacement/1"),
      std::string::npos);
  EXPECT_NE(
      error_of(with(kBlock, R"("model": "neo_hookean")", R"("model": "neohookean")")).find("neo_hookean"),
      std::string::npos);
}

TEST(PvdWriter, WritesAValidSeriesAfterEveryStep) {
  const std::string dir = "output/test_elasticity/pvd";
  fs::remove_all(dir);
  io::PvdWriter pvd(MPI_COMM_SELF, dir, "series");
  pvd.add(0.0, dir + "/series_000000.vtu");
  pvd.add(0.5, dir + "/series_000001.pvtu");
  vtkSmartPointer<vtkXMLDataElement> root;
  root.TakeReference(vtkXMLUtilities::ReadElementFromFile(pvd.path().c_str()));
  ASSERT_TRUE(root) << "the index must parse as XML";
  EXPECT_STREQ(root->GetName(), "VTKFile");
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  vtkXMLDataElement* collection = root->GetNestedElement(0);
  ASSERT_EQ(collection->GetNumberOfNestedElements(), 2);
  EXPECT_STREQ(collection->GetNestedElement(1)->GetAttribute("timestep"), "0.5");
  EXPECT_STREQ(collection->GetNestedElement(1)->GetAttribute("file"), "series_000001.pvtu");
}

TEST(ElasticityRun, BlockCompressionReachesThePrescribedDisplacement) {
  const auto cfg = parse(kBlock);
  fs::remove_all(cfg.output.directory);
  const auto result = apps::run(cfg, MPI_COMM_SELF);
  ASSERT_EQ(result.load_steps.size(), 2u);
  EXPECT_NEAR(result.load_steps.back().load, 1.0, 1e-14);
  EXPECT_NEAR(result.max_displacement, 0.3, 0.05) << "the top edge moves by 0.3, the sides bulge a little";
  EXPECT_GT(result.min_det_F, 0.2);
  EXPECT_LT(result.min_det_F, 1.0);
  EXPECT_EQ(result.vtk_files.size(), 3u) << "initial state and both load steps";
  EXPECT_TRUE(fs::exists(result.output_file));
  for (const auto& f : result.vtk_files) EXPECT_TRUE(fs::exists(f)) << f;
}

TEST(ElasticityRun, MultigridNewtonStepsGiveTheDirectSolversResult) {
  // "pc_type": "mg": GMRES with geometric multigrid on the mesh hierarchy (Galerkin coarse
  // operators of every Newton Jacobian) instead of LU: the same load path and solution.
  const std::string refined = with(kBlock, R"("cells": [4, 4])", R"("cells": [4, 4], "refinements": 2)");
  auto lu_cfg = parse(refined);
  auto mg_cfg = parse(with(refined, R"("load_stepping")", R"("solver": {"pc_type": "mg"}, "load_stepping")"));
  ASSERT_EQ(mg_cfg.solver.pc_type, "mg");
  const auto lu = apps::run(lu_cfg, MPI_COMM_SELF, {.write_output = false});
  const auto mg = apps::run(mg_cfg, MPI_COMM_SELF, {.write_output = false});
  EXPECT_EQ(mg.newton_iterations, lu.newton_iterations);
  EXPECT_NEAR(mg.max_displacement, lu.max_displacement, 1e-8);
  EXPECT_NEAR(mg.min_det_F, lu.min_det_F, 1e-8);
}

TEST(ElasticityRun, GearExampleSwingsUnderGravity) {
  std::ifstream in("examples/gear_transient.json");
  ASSERT_TRUE(in) << "run from the repository root";
  nlohmann::json json = nlohmann::json::parse(in, nullptr, true, true);
  json["time"]["end"] = 0.05;
  json["verbosity"] = "warning";
  json["mesh"]["cells"] = {10, 10};
  const auto cfg = io::parse_elasticity_config(json, "examples/gear_transient.json");
  const auto result = apps::run(cfg, MPI_COMM_SELF, {.write_output = false});
  EXPECT_EQ(result.time_steps, 5);
  EXPECT_GT(result.max_displacement, 1e-3) << "gravity must move the gear";
  EXPECT_LT(result.max_displacement, 0.2);
  EXPECT_GT(result.min_det_F, 0.5);
}

TEST(ElasticityRun, FailingLoadKeepsTheLastConvergedStateWritten) {
  // Pushing the top edge 1.2 below its height of 1 cannot be reached without inverting the block.
  auto cfg = parse(with(kBlock, R"("displacement": [0, -0.3])", R"("displacement": [0, -1.2])"));
  cfg.output.directory = "output/test_elasticity/failing";
  cfg.load_stepping.min_increment = 0.1;
  fs::remove_all(cfg.output.directory);
  try {
    apps::run(cfg, MPI_COMM_SELF);
    FAIL() << "expected warpfem::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("quasi-static solve failed"), std::string::npos) << e.what();
    // The error names the config and the settings that could make it converge.
    EXPECT_EQ(e.context().file, "test.json");
    EXPECT_EQ(e.context().key_path, "/load_stepping");
  }
  EXPECT_TRUE(fs::exists(cfg.output.directory + "/block.pvd"));
  EXPECT_TRUE(fs::exists(cfg.output.directory + "/block_000001.vtu"))
      << "the converged step s = 0.5 is written";
}
