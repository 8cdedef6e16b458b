// Bad input must be refused with a message naming the file, the field and a
// fix, never crash the program or be silently replaced by something else.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "core/mesh/polygon_mesher.hpp"
#include "core/polygon.hpp"
#include "io/config_field.hpp"
#include "io/elasticity_config.hpp"
#include "io/expression.hpp"
#include "io/run_config.hpp"

using namespace warpfem;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json valid_config() {
  return json::parse(R"json({
    "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
    "mesh": {"max_edge_length": 0.25, "refinements": 1},
    "problem": {"source": "1", "dirichlet": [{"edges": "all", "value": 0}]},
    "output": {"directory": "output/test"}
  })json");
}

json valid_elasticity() {
  return json::parse(R"json({
    "map": {"type": "identity", "source": [[0,0],[1,0],[1,1],[0,1]]},
    "mesh": {"max_edge_length": 0.5},
    "problem": {"type": "elasticity", "material": {"E": 100, "nu": 0.3},
                "dirichlet": [{"edges": [3], "displacement": [0, 0]}]}
  })json");
}

template <class Parse>
std::string error_of(Parse parse) {
  try {
    parse();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

std::string run_error(const json& j) {
  return error_of([&] { io::parse_run_config(j, "config.json"); });
}
std::string elasticity_error(const json& j) {
  return error_of([&] { io::parse_elasticity_config(j, "config.json"); });
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "message: " << text << "\nexpected to contain: " << part;
}

/// A scratch directory removed at the end of the test.
struct ScratchDir {
  fs::path path;
  ScratchDir() {
    path = fs::temp_directory_path() / ("warpfem_input_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return (path / name).string();
  }
};

}  // namespace

// --- JSON documents -------------------------------------------------------

TEST(InputValidation, ExcerptOfDeeplyNestedValueIsShortAndDoesNotRecurse) {
  json v = 1;
  for (int i = 0; i < 1000000; ++i) {
    json a = json::array();
    a.push_back(std::move(v));
    v = std::move(a);
  }
  const std::string s = io::json_excerpt(v);
  EXPECT_LE(s.size(), 60u);
  EXPECT_EQ(s.substr(0, 4), "[[[[");
  // The same through an error message: a config whose root is such an array.
  expect_contains(error_of([&] { io::ConfigNode(v, "deep.json"); }), "deep.json: /: expected an object");
}

TEST(InputValidation, DeeplyNestedDocumentIsRefusedWhileParsing) {
  ScratchDir dir;
  const std::string file = dir.write("deep.json", std::string(200000, '[') + std::string(200000, ']'));
  const std::string m = error_of([&] { io::ConfigNode::parse_file(file); });
  expect_contains(m, "deep.json: the document nests arrays and objects deeper than 64 levels");
}

TEST(InputValidation, DuplicateKeyIsRefusedWithKeyAndLine) {
  ScratchDir dir;
  const std::string file =
      dir.write("dup.json",
                "{\n  \"mesh\": {\"refinements\": 1},\n  // \"mesh\" in a comment\n"
                "  \"problem\": {\"source\": 1, \"dirichlet\": []},\n  \"mesh\": {}\n}\n");
  const std::string m = error_of([&] { io::ConfigNode::parse_file(file); });
  expect_contains(m, "dup.json: duplicate key \"mesh\" at line 5");
  // The same key in different objects is fine.
  const std::string ok = dir.write("ok.json", R"({"a": {"x": 1}, "b": {"x": 2}, "c": [{"x": 1}, {"x": 2}]})");
  EXPECT_NO_THROW(io::ConfigNode::parse_file(ok));
}

TEST(InputValidation, DirectoryAsConfigSaysSo) {
  ScratchDir dir;
  const std::string m = error_of([&] { io::ConfigNode::parse_file(dir.path.string()); });
  expect_contains(m, "is a directory");
  EXPECT_EQ(m.find("invalid JSON"), std::string::npos) << m;
}

TEST(InputValidation, OverflowingNumberIsAConfigError) {
  ScratchDir dir;
  // The same token inside a string and a comment first: the number's own place is reported.
  const std::string file =
      dir.write("big.json", "{\"name\": \"1e999\", // 1e999\n \"mesh\": {\"max_edge_length\": 1e999}}");
  const std::string m = error_of([&] { io::ConfigNode::parse_file(file); });
  expect_contains(m, "big.json: invalid JSON at line 2, column 30: ");
  expect_contains(m, "1e999");
}

TEST(InputValidation, RangeMessagesPrintBoundsExactly) {
  json j = valid_config();
  j["mesh"]["shape_bound"] = 0.1;
  expect_contains(run_error(j), "/mesh/shape_bound: expected a number >= 0.125, got 0.1");
  j = valid_config();
  j["map"]["min_interval"] = 0;
  expect_contains(run_error(j), "/map/min_interval: expected a number in [1e-12, 1], got 0");
  json e = valid_elasticity();
  e["problem"]["analysis"] = "transient";
  e["time"] = {{"step", 0}};
  expect_contains(elasticity_error(e), "/time/step: expected a number > 0, got 0");
}

// --- polygons ---------------------------------------------------------------

TEST(InputValidation, PolygonFileLinesThatAreNotVerticesAreRefused) {
  ScratchDir dir;
  for (const std::string bad : {"nan,0", "l,1", "1e999,1", "1,2,3", "0x"}) {
    const std::string file = dir.write("poly.txt", "# unit square\n0,0\n1,0\n\n" + bad + "\n1,1\n0,1\n");
    json j = valid_config();
    j["map"]["source"] = file;
    const std::string m = run_error(j);
    expect_contains(m, file + ": line 5: \"" + bad + "\" is not a vertex");
  }
  const std::string good = dir.write("good.txt", "0 0  # first\r\n1;0\n\n1,1\n0\t1\n");
  json j = valid_config();
  j["map"]["source"] = good;
  EXPECT_EQ(io::parse_run_config(j, "config.json").map.source->size(), 4);
}

TEST(InputValidation, HugeCoordinatesAreRefusedBeforeMeshing) {
  json j = valid_config();
  j["map"]["source"] = json::parse("[[0,0],[1e308,0],[1,1],[0,1]]");
  const std::string m = run_error(j);
  expect_contains(m, "config.json: /map/source: source polygon: vertex 1 (1e+308, 0) lies beyond");
  expect_contains(m, "rescale");
}

TEST(InputValidation, TinyPolygonIsDegenerateNotClockwise) {
  json j = valid_config();
  j["map"]["source"] = json::parse("[[0,0],[1e-300,0],[1e-300,1e-300],[0,1e-300]]");
  const std::string m = run_error(j);
  expect_contains(
      m, "/map/source: source polygon is degenerate or too small: its bounding box is 1e-300 x 1e-300");
  EXPECT_EQ(m.find("clockwise"), std::string::npos) << m;
  // Far from the origin, a polygon smaller than the doubles there can resolve.
  j["map"]["source"] = json::parse("[[1e9,0],[1.000000000001e9,0],[1.000000000001e9,1e-3],[1e9,1e-3]]");
  expect_contains(run_error(j), "degenerate or too small");
  // Clockwise polygons name the real area.
  j["map"]["source"] = json::parse("[[0,0],[0,1e-3],[1e-3,1e-3],[1e-3,0]]");
  expect_contains(run_error(j), "oriented clockwise (signed area -1e-06)");
}

// --- fields that used to be misread ----------------------------------------

TEST(InputValidation, EmptyEdgeListIsRefused) {
  json j = valid_config();
  j["problem"]["dirichlet"][0]["edges"] = json::array();
  expect_contains(run_error(j), "/problem/dirichlet/0/edges: an empty list selects no edge");
  expect_contains(run_error(j), "omit the key");
  json e = valid_elasticity();
  e["problem"]["dirichlet"][0]["edges"] = json::array();
  expect_contains(elasticity_error(e), "/problem/dirichlet/0/edges: an empty list selects no edge");
}

TEST(InputValidation, LameParametersComeInPairs) {
  json e = valid_elasticity();
  e["problem"]["material"] = {{"lambda", 1000}};
  expect_contains(elasticity_error(e), "/problem/material/mu: \"lambda\" is given without \"mu\"");
  e["problem"]["material"] = {{"mu", 1000}};
  expect_contains(elasticity_error(e), "/problem/material/lambda: \"mu\" is given without \"lambda\"");
  e["problem"]["material"] = {{"lambda", 1000}, {"mu", 500}};
  const io::ElasticityConfig cfg = io::parse_elasticity_config(e, "config.json");
  EXPECT_EQ(cfg.problem.material.lambda, 1000);
  EXPECT_EQ(cfg.problem.material.mu, 500);
}

TEST(InputValidation, AssignmentsAndListsAreNotExpressions) {
  for (const std::string bad : {"x=3", "y = 1", "1,2", "sin(x), 2"}) {
    const std::string m = error_of([&] { io::Expression(bad, "f.json", "/problem/source"); });
    expect_contains(m, "f.json: /problem/source: expression \"" + bad + "\"");
  }
  for (const std::string good : {"x<=1", "x>=1", "x!=1", "x==1", "min(1, 2)", "(x<0.5) ? 1 : 2"})
    EXPECT_NO_THROW(io::Expression{good}) << good;
  json j = valid_config();
  j["problem"]["source"] = "x=3";
  expect_contains(run_error(j), "/problem/source: expression \"x=3\" assigns a value");
}

TEST(InputValidation, PureNeumannPoissonIsRefused) {
  json j = valid_config();
  j["problem"].erase("dirichlet");
  j["problem"]["neumann"] = json::parse(R"([{"value": 0}])");
  expect_contains(run_error(j), "/problem/dirichlet: only Neumann conditions");
}

TEST(InputValidation, UnknownSolverTypesNameTheKeyAndTheChoices) {
  json j = valid_config();
  j["solver"] = {{"ksp_type", "cgg"}};
  std::string m = run_error(j);
  expect_contains(m, "config.json: /solver/ksp_type: unknown PETSc Krylov method \"cgg\"");
  expect_contains(m, "(fix: did you mean \"cg\"? use one of ");
  expect_contains(m, " cg, ");
  j["solver"] = {{"pc_type", "jacobbi"}};
  m = run_error(j);
  expect_contains(m, "/solver/pc_type: unknown PETSc preconditioner \"jacobbi\"");
  expect_contains(m, " jacobi, ");
  json e = valid_elasticity();
  e["solver"] = {{"pc_type", "luu"}};
  expect_contains(elasticity_error(e), "/solver/pc_type: unknown PETSc preconditioner \"luu\"");
}

// --- sizes ------------------------------------------------------------------

TEST(InputValidation, TooManyRefinementsAreRefusedBeforeAllocating) {
  json j = valid_config();
  j["mesh"]["refinements"] = 12;
  const std::string m = run_error(j);
  expect_contains(m, "config.json: /mesh/refinements: the discretization would have at least ");
  expect_contains(m, "GiB");
  expect_contains(m, "memory_gb");
}

TEST(InputValidation, TinyEdgeLengthsAreRefusedWithTheEstimate) {
  for (const double h : {1e-300, 1e-5}) {
    json j = valid_config();
    j["mesh"] = {{"max_edge_length", h}};
    expect_contains(run_error(j), "/mesh/max_edge_length: the discretization would have at least ");
    j["mesh"]["type"] = "pullback";
    j["map"] = json::parse(R"({"type": "composite_mean_value", "source": [[0,0],[1,0],[1,1],[0,1]],
                               "target": [[0,0],[2,0],[2,1],[0,1]]})");
    expect_contains(run_error(j), "/mesh/max_edge_length: the discretization would have at least ");
  }
}

TEST(InputValidation, HugeStructuredGridIsRefused) {
  json j = valid_config();
  j["mesh"] = {{"type", "structured"}, {"cells", 100000}, {"refinements", 0}};
  j["problem"]["order"] = 2;
  expect_contains(run_error(j), "/mesh/cells: the discretization would have at least 1e+10 cells");
}

TEST(InputValidation, DenseHarmonicSystemsAreRefused) {
  json j = valid_config();
  j["map"] = json::parse(R"({"type": "composite_harmonic", "harmonic_method": "bem", "boundary_nodes": 100000,
                             "source": [[0,0],[1,0],[1,1],[0,1]], "target": [[0,0],[2,0],[2,1],[0,1]]})");
  expect_contains(run_error(j), "/map/boundary_nodes: bem with 100000 boundary nodes needs dense matrices");
}

TEST(InputValidation, LimitsOverrideTheMachineMemory) {
  json j = valid_config();
  j["mesh"]["refinements"] = 6;  // about 2e5 P1 DOFs: well within any machine
  EXPECT_NO_THROW(io::parse_run_config(j, "config.json"));
  j["limits"] = {{"memory_gb", 0.001}};
  expect_contains(run_error(j), "/mesh/refinements: the discretization would have at least");
  j["limits"] = {{"memory_gb", 0}};
  expect_contains(run_error(j), "/limits/memory_gb: expected a number > 0");
  j["limits"] = {{"memory_GB", 1}};
  expect_contains(run_error(j), "/limits/memory_GB: unknown key");
}

TEST(InputValidation, TransientRunsWithTooManyStepsOrFilesAreRefused) {
  json e = valid_elasticity();
  e["problem"]["analysis"] = "transient";
  e["time"] = {{"step", 1e-9}, {"end", 1}};
  expect_contains(elasticity_error(e), "/time/step: end 1 / step 1e-09 makes 1e+09 time steps");
  e["time"] = {{"step", 1e-4}, {"end", 1}};
  const std::string m = elasticity_error(e);
  expect_contains(m, "/output/every: writing every 1 of 1000");
  expect_contains(m, "output files, more than the limit of 10000");
  e["output"] = {{"every", 10}};
  EXPECT_NO_THROW(io::parse_elasticity_config(e, "config.json"));
  e["output"] = {{"vtk", false}};
  EXPECT_NO_THROW(io::parse_elasticity_config(e, "config.json"));
}

TEST(InputValidation, MesherRefusesAnEdgeBoundItCannotSquare) {
  const Polygon square = Polygon::checked({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  // The mesher names the parameter; io locates it in the config.
  const std::string m = error_of([&] { warpfem::mesh_polygon(square, {.max_edge_length = 1e-300}); });
  expect_contains(m, "mesh.max_edge_length: edge length bound 1e-300 cannot be used");
  const std::string located = error_of([&] {
    try {
      warpfem::mesh_polygon(square, {.max_edge_length = 1e-300});
    } catch (const Error& e) {
      throw io::in_config(e, "config.json");
    }
  });
  expect_contains(located, "config.json: /mesh/max_edge_length: edge length bound 1e-300 cannot be used");
}
