// Malformed configs must be rejected with a message naming the field and the fix.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <utility>

#include "core/error.hpp"
#include "io/elasticity_config.hpp"
#include "io/run_config.hpp"

using namespace warpfem;
using nlohmann::json;

namespace {

json valid_config() {
  return json::parse(R"json({
    "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
    "mesh": {"max_edge_length": 0.25, "refinements": 1},
    "problem": {"source": "1", "dirichlet": [{"edges": "all", "value": 0}]},
    "output": {"directory": "output/test"}
  })json");
}

std::string error_of(const json& j) {
  try {
    io::parse_run_config(j, "config.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "message: " << text << "\nexpected to contain: " << part;
}

}  // namespace

TEST(RunConfig, ValidConfigParsesWithDefaults) {
  const io::RunConfig cfg = io::parse_run_config(valid_config(), "config.json");
  EXPECT_EQ(cfg.mesh.refinements, 1);
  EXPECT_EQ(cfg.poisson.order, 1);
  EXPECT_EQ(cfg.solver.linear.ksp_type, "cg");
  EXPECT_EQ(cfg.map.source->size(), 4);
  ASSERT_EQ(cfg.poisson.dirichlet.size(), 1u);
  EXPECT_TRUE(cfg.poisson.dirichlet[0].edges.empty());
}

TEST(RunConfig, WrongTypeNamesKeyPathAndValue) {
  json j = valid_config();
  j["mesh"]["refinements"] = "two";
  EXPECT_EQ(error_of(j), "config.json: /mesh/refinements: expected an integer in [0, 12], got \"two\"");
}

TEST(RunConfig, UnknownKeyIsRejectedWithSuggestion) {
  json j = valid_config();
  j["mesh"]["refinement"] = 2;
  const std::string m = error_of(j);
  expect_contains(m, "config.json: /mesh/refinement: unknown key \"refinement\"");
  expect_contains(m, "did you mean \"refinements\"?");
}

TEST(RunConfig, UnknownTopLevelKeyIsRejected) {
  json j = valid_config();
  j["solvr"] = json::object();
  expect_contains(error_of(j), "/solvr: unknown key \"solvr\"");
}

TEST(RunConfig, ClockwisePolygonNamesFieldAndFix) {
  json j = valid_config();
  j["map"]["source"] = json::parse("[[0,0],[0,1],[1,1],[1,0]]");
  const std::string m = error_of(j);
  expect_contains(m, "config.json: /map/source: source polygon is oriented clockwise");
  expect_contains(m, "reverse the vertex order");
}

TEST(RunConfig, SelfIntersectingPolygonIsRejected) {
  json j = valid_config();
  j["map"]["source"] = json::parse("[[0,0],[1,1],[1,0],[0,1]]");
  expect_contains(error_of(j), "/map/source: source polygon is not simple: edge 0 and edge 2 intersect");
}

TEST(RunConfig, VertexCountMismatchIsRejected) {
  json j = valid_config();
  j["map"]["type"] = "composite_mean_value";
  j["map"]["target"] = json::parse("[[0,0],[2,0],[0,2]]");
  expect_contains(error_of(j), "/map/target: source polygon has 4 vertices but target polygon has 3");
}

TEST(RunConfig, BadExpressionNamesField) {
  json j = valid_config();
  j["problem"]["source"] = "sin(pi*x";
  const std::string m = error_of(j);
  expect_contains(m, "config.json: /problem/source: cannot parse expression \"sin(pi*x\"");
}

TEST(RunConfig, UnknownVariableInBoundaryValue) {
  json j = valid_config();
  j["problem"]["dirichlet"][0]["value"] = "x + w";
  expect_contains(error_of(j), "/problem/dirichlet/0/value: cannot parse expression \"x + w\"");
}

TEST(RunConfig, EdgeIndexOutOfRange) {
  json j = valid_config();
  j["problem"]["dirichlet"][0]["edges"] = json::parse("[0, 7]");
  expect_contains(error_of(j), "/problem/dirichlet/0/edges/1: expected an edge index in [0, 3], got 7");
}

TEST(RunConfig, UnknownChoiceListsAlternatives) {
  json j = valid_config();
  j["map"]["type"] = "magic";
  const std::string m = error_of(j);
  expect_contains(m, "/map/type: unknown value \"magic\"");
  expect_contains(m, "use one of \"identity\"");
}

TEST(RunConfig, GeometryStorageIsAChoice) {
  json j = valid_config();
  EXPECT_EQ(io::parse_run_config(j, "config.json").poisson.geometry, "streamed");  // one pass: streamed
  j["problem"]["exact_solution"] = "x";
  EXPECT_EQ(io::parse_run_config(j, "config.json").poisson.geometry, "cached");  // error norms: a second pass
  j["problem"].erase("exact_solution");
  j["problem"]["geometry"] = "cached";
  EXPECT_EQ(io::parse_run_config(j, "config.json").poisson.geometry, "cached");
  j["problem"]["geometry"] = "streamed";
  EXPECT_EQ(io::parse_run_config(j, "config.json").poisson.geometry, "streamed");
  j["problem"]["geometry"] = "lazy";
  const std::string m = error_of(j);
  expect_contains(m, "/problem/geometry: unknown value \"lazy\"");
  expect_contains(m, "\"streamed\"");
}

TEST(RunConfig, OutputCompressionAndCellsAreChoices) {
  json j = valid_config();
  const auto defaults = io::parse_run_config(j, "config.json").output;
  EXPECT_EQ(defaults.compression, "none");
  EXPECT_EQ(defaults.cells, "curved");
  EXPECT_EQ(defaults.vtk_order, 0);
  j["output"]["compression"] = "lz4";
  j["output"]["cells"] = "linear";
  const auto chosen = io::parse_run_config(j, "config.json").output;
  EXPECT_EQ(chosen.compression, "lz4");
  EXPECT_EQ(chosen.vtk_order, 1);  // linear cells: the vertices only
  j["output"]["compression"] = "gzip";
  std::string m = error_of(j);
  expect_contains(m, "config.json: /output/compression: unknown value \"gzip\"");
  expect_contains(m, "\"none\", \"lz4\", \"zlib\"");
  j["output"]["compression"] = "zlib";
  j["output"]["cells"] = "quadratic";
  m = error_of(j);
  expect_contains(m, "config.json: /output/cells: unknown value \"quadratic\"");
  expect_contains(m, "\"curved\", \"linear\"");
  j["output"]["cells"] = "linear";
  j["output"]["vtk_order"] = 2;
  expect_contains(error_of(j), "config.json: /output/vtk_order: \"cells\": \"linear\" writes straight cells");
}

TEST(ElasticityConfig, OutputCompressionAndCellsAreChoices) {
  json j = json::parse(R"json({
    "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
    "problem": {"type": "elasticity", "material": {"model": "neo_hookean", "E": 1000, "nu": 0.3},
                "dirichlet": [{"edges": [0], "displacement": [0, 0]}]},
    "output": {"compression": "zlib", "cells": "linear"}
  })json");
  const auto output = io::parse_elasticity_config(j, "block.json").output;
  EXPECT_EQ(output.compression, "zlib");
  EXPECT_EQ(output.vtk_order, 1);
  j["output"]["compression"] = "bzip2";
  try {
    io::parse_elasticity_config(j, "block.json");
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    expect_contains(e.what(), "block.json: /output/compression: unknown value \"bzip2\"");
  }
}

TEST(RunConfig, MultigridSettingsAreChoices) {
  using S = multigrid::MultigridSettings;
  json j = valid_config();
  const io::RunConfig defaults = io::parse_run_config(j, "config.json");
  EXPECT_EQ(defaults.solver.multigrid.smoother, S::Smoother::automatic);
  EXPECT_EQ(defaults.solver.multigrid.cycle, S::Cycle::v);
  EXPECT_EQ(defaults.solver.multigrid.coarse_operators, S::CoarseOperators::rediscretization);
  EXPECT_EQ(defaults.solver.multigrid.smoothing_steps, 0);  // automatic: smoothing_steps_for()
  EXPECT_EQ(defaults.solver.multigrid.chebyshev_bounds, S::ChebyshevBounds::automatic);
  j["solver"]["multigrid"] = json::parse(R"({"chebyshev_bounds": "estimate"})");
  EXPECT_EQ(io::parse_run_config(j, "config.json").solver.multigrid.chebyshev_bounds,
            S::ChebyshevBounds::estimate);
  j["solver"]["multigrid"] = json::parse(R"({"chebyshev_bounds": "gershgorin"})");
  EXPECT_EQ(io::parse_run_config(j, "config.json").solver.multigrid.chebyshev_bounds,
            S::ChebyshevBounds::gershgorin);
  EXPECT_EQ(defaults.solver.multigrid.chebyshev_kernel, S::ChebyshevKernel::fused_single);
  for (const auto& [name, kernel] : {std::pair{"petsc", S::ChebyshevKernel::petsc},
                                     std::pair{"fused_double", S::ChebyshevKernel::fused_double}}) {
    j["solver"]["multigrid"] = json{{"chebyshev_kernel", name}};
    EXPECT_EQ(io::parse_run_config(j, "config.json").solver.multigrid.chebyshev_kernel, kernel) << name;
  }
  j["solver"]["multigrid"] = json::parse(R"({"chebyshev_kernel": "fast"})");
  expect_contains(error_of(j), "/solver/multigrid/chebyshev_kernel");
  EXPECT_EQ(defaults.solver.multigrid.prolongation, S::Prolongation::geometric);
  j["solver"]["multigrid"] = json::parse(R"({"prolongation": "smoothed", "smoother": "chebyshev_sor"})");
  EXPECT_EQ(io::parse_run_config(j, "config.json").solver.multigrid.prolongation, S::Prolongation::smoothed);
  j["solver"]["multigrid"] = json::parse(R"({"prolongation": "smooth"})");
  expect_contains(error_of(j), "/solver/multigrid/prolongation: unknown value \"smooth\"");
  // Smoothed prolongations bring Galerkin operators: asking for rediscretized ones, or for
  // Gershgorin bounds (which hold for rediscretized P1 levels only), is refused.
  j["solver"]["multigrid"] =
      json::parse(R"({"prolongation": "smoothed", "coarse_operators": "rediscretization"})");
  expect_contains(error_of(j),
                  "/solver/multigrid/coarse_operators: smoothed prolongations come with Galerkin");
  j["solver"]["multigrid"] = json::parse(R"({"prolongation": "smoothed", "chebyshev_bounds": "gershgorin"})");
  expect_contains(error_of(j), "/solver/multigrid/chebyshev_bounds: \"gershgorin\" bounds");
  j["solver"]["multigrid"] = json::parse(R"({"chebyshev_bounds": "gershgorin", "smoother": "sor"})");
  expect_contains(error_of(j), "/solver/multigrid/chebyshev_bounds: \"gershgorin\" bounds");
  j["solver"]["multigrid"] = json::parse(R"({"chebyshev_bounds": "ssor", "smoother": "chebyshev_sor"})");
  EXPECT_EQ(io::parse_run_config(j, "config.json").solver.multigrid.chebyshev_bounds,
            S::ChebyshevBounds::ssor);
  j["solver"]["multigrid"] = json::parse(R"({"chebyshev_bounds": "ssor"})");
  expect_contains(error_of(j), "/solver/multigrid/chebyshev_bounds: \"ssor\" bounds");
  j["solver"]["multigrid"] = json::parse(
      R"({"smoother": "chebyshev_sor", "cycle": "w", "coarse_operators": "galerkin", "smoothing_steps": 3})");
  const io::RunConfig cfg = io::parse_run_config(j, "config.json");
  EXPECT_EQ(cfg.solver.multigrid.smoother, S::Smoother::chebyshev_sor);
  EXPECT_EQ(cfg.solver.multigrid.cycle, S::Cycle::w);
  EXPECT_EQ(cfg.solver.multigrid.coarse_operators, S::CoarseOperators::galerkin);
  EXPECT_EQ(cfg.solver.multigrid.smoothing_steps, 3);
  j["solver"]["multigrid"]["smoother"] = "gauss";
  expect_contains(error_of(j), "/solver/multigrid/smoother: unknown value \"gauss\"");
  j["solver"]["multigrid"] = json::parse(R"({"smoothing_steps": -1})");
  expect_contains(error_of(j), "/solver/multigrid/smoothing_steps");
  j["solver"]["multigrid"] = json::parse(R"({"cycles": "w"})");
  expect_contains(error_of(j), "/solver/multigrid/cycles: unknown key");
  // Settings that would be silently ignored are refused.
  j["solver"]["multigrid"] = json::parse(R"({"cycle": "w"})");
  j["solver"]["pc_type"] = "hypre";
  expect_contains(error_of(j),
                  "/solver/multigrid: multigrid settings are given, but \"pc_type\" is \"hypre\"");
}

TEST(RunConfig, MissingBoundaryConditionIsAnError) {
  json j = valid_config();
  j["problem"].erase("dirichlet");
  expect_contains(error_of(j), "/problem/dirichlet: no boundary condition given");
}

TEST(RunConfig, MissingMapIsAnError) {
  json j = valid_config();
  j.erase("map");
  expect_contains(error_of(j), "config.json: /map: missing required field");
}

TEST(RunConfig, NegativeEdgeLengthIsAnError) {
  json j = valid_config();
  j["mesh"]["max_edge_length"] = -1;
  expect_contains(error_of(j), "/mesh/max_edge_length: expected a number >= 0");
}

TEST(RunConfig, SyntaxErrorNamesLineAndColumn) {
  const std::string path = "output/test_config_syntax.json";
  std::filesystem::create_directories("output");
  {
    std::ofstream out(path);
    out << "{\n  \"map\": {\n    \"type\": \"identity\"\n    \"source\": []\n  }\n}\n";
  }
  try {
    io::load_run_config(path);
    FAIL() << "expected a syntax error";
  } catch (const Error& e) {
    expect_contains(e.what(), path + ": invalid JSON at line 4");
  }
}

TEST(RunConfig, MissingFileIsAnError) {
  try {
    io::load_run_config("does/not/exist.json");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    expect_contains(e.what(), "does/not/exist.json: cannot open config file");
  }
}

TEST(RunConfig, PolygonFromFileRelativeToConfig) {
  std::filesystem::create_directories("output/polyfile");
  {
    std::ofstream out("output/polyfile/square.csv");
    out << "# x, y\n0,0\n1,0\n1 1\n0,1\n";
  }
  json j = valid_config();
  j["map"]["source"] = "square.csv";
  const auto cfg = io::parse_run_config(j, "output/polyfile/config.json");
  EXPECT_EQ(cfg.map.source->size(), 4);
  EXPECT_DOUBLE_EQ(cfg.map.source->signed_area(), 1.0);
}
