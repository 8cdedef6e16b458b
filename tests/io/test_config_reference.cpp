// The parameter tables: what they bind is what configs set, errors of lower layers
// reach the user as JSON pointers, and the committed reference documents are the
// generated ones.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "fem/hierarchy/mesh_parameters.hpp"
#include "io/config_field.hpp"
#include "io/config_reference.hpp"
#include "io/elasticity_parameters.hpp"
#include "io/parameter_reader.hpp"
#include "io/run_parameters.hpp"
#include "mapping/map_parameters.hpp"
#include "multigrid/multigrid_parameters.hpp"

namespace warpfem::io {
namespace {

/// A valid value different from `current` (the default) for each kind of parameter.
template <class S>
nlohmann::json other_value(const Parameter<S>& p, const ParameterValue& current) {
  switch (p.kind) {
    case ParameterKind::boolean: return !std::get<bool>(current);
    case ParameterKind::integer: {
      const long v = std::get<long>(current);
      return v == static_cast<long>(p.min) || !std::isfinite(p.min) ? v + 1 : static_cast<long>(p.min);
    }
    case ParameterKind::number:
    case ParameterKind::positive: {
      const double v = std::get<double>(current);
      const double low = std::isfinite(p.min) ? p.min : 0.5;
      return v == low ? (std::isfinite(p.max) ? p.max : low + 1)
                      : (p.kind == ParameterKind::positive ? 0.5 : low);
    }
    case ParameterKind::choice:
      return std::get<std::string>(current) == p.choices.back() ? p.choices.front() : p.choices.back();
    case ParameterKind::expression: return "x*y + 3";
    case ParameterKind::petsc_ksp: return std::get<std::string>(current) == "gmres" ? "cg" : "gmres";
    case ParameterKind::petsc_pc: return std::get<std::string>(current) == "jacobi" ? "lu" : "jacobi";
    case ParameterKind::text:
    case ParameterKind::other: break;
  }
  return std::get<std::string>(current) + "x";
}

/// Every bound parameter: absent keys keep the struct's default, a given value lands in its member.
template <class S>
void expect_table_binds_members(const ParameterTable<S>& table) {
  const S defaults{};
  {
    S s{};
    const nlohmann::json empty = nlohmann::json::object();
    read_parameters(ConfigNode(empty, "t.json"), table, s);
    for (const auto& p : table.entries())
      if (!p.manual) {
        EXPECT_EQ(p.get(s), p.get(defaults)) << table.section() << "." << p.name;
      }
  }
  for (const auto& p : table.entries()) {
    if (p.manual) continue;
    nlohmann::json json = nlohmann::json::object();
    json[p.name] = other_value(p, p.get(defaults));
    S s{};
    read_parameters(ConfigNode(json, "t.json"), table, s);
    EXPECT_NE(p.get(s), p.get(defaults)) << table.section() << "." << p.name << " = " << json.dump();
    const ParameterValue v = p.get(s);
    const nlohmann::json back = std::visit([](const auto& x) { return nlohmann::json(x); }, v);
    EXPECT_EQ(back, json[p.name]) << table.section() << "." << p.name;
  }
}

TEST(ParameterTables, BindTheMembersTheyName) {
  expect_table_binds_members(mapping::map_parameters());
  expect_table_binds_members(fem::mesh_parameters());
  expect_table_binds_members(multigrid::multigrid_parameters());
  expect_table_binds_members(poisson_parameters());
  expect_table_binds_members(solver_parameters());
  expect_table_binds_members(output_parameters());
  expect_table_binds_members(limits_parameters());
  expect_table_binds_members(elasticity_parameters());
  expect_table_binds_members(load_stepping_parameters());
  expect_table_binds_members(time_parameters());
  expect_table_binds_members(newton_parameters());
  expect_table_binds_members(elasticity_output_parameters());
}

TEST(ParameterTables, RangesGiveTheReadersMessages) {
  const nlohmann::json json = {{"refinements", 13}};
  fem::MeshSpec spec;
  try {
    read_parameters(ConfigNode(json, "run.json", "/mesh"), fem::mesh_parameters(), spec);
    FAIL() << "13 refinements accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "run.json: /mesh/refinements: expected an integer in [0, 12], got 13");
  }
}

TEST(ConfigField, ParameterIdsBecomeJsonPointers) {
  EXPECT_EQ(json_pointer(multigrid::multigrid_parameters().field("smoother")), "/solver/multigrid/smoother");
  EXPECT_EQ(json_pointer(mapping::map_parameters().field("min_interval")), "/map/min_interval");
  const Error lower(
      "diverged",
      {.file = "", .key_path = "solver.max_iterations", .hint = "raise solver.max_iterations or mesh.x"});
  EXPECT_STREQ(in_config(lower, "run.json").what(),
               "run.json: /solver/max_iterations: diverged (fix: raise /solver/max_iterations or /mesh/x)");
  const Error gmsh("bad area", {.file = "a.msh", .key_path = "mesh.file", .hint = ""});
  EXPECT_STREQ(in_config(gmsh, "run.json").what(), "a.msh: /mesh/file: bad area");
  const Error located("bad", {.file = "run.json", .key_path = "/mesh/refinements", .hint = "mesh.x"});
  EXPECT_STREQ(in_config(located, "other.json").what(), "run.json: /mesh/refinements: bad (fix: mesh.x)");
  const Error plain("no field", {.file = "", .key_path = "", .hint = "h"});
  EXPECT_STREQ(in_config(plain, "run.json").what(), "no field (fix: h)");
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The differing lines of two texts, for a readable failure.
std::string line_diff(const std::string& committed, const std::string& generated) {
  std::istringstream a(committed), b(generated);
  std::ostringstream out;
  std::string la, lb;
  int line = 0, shown = 0;
  while (shown < 40) {
    const bool ha = static_cast<bool>(std::getline(a, la)), hb = static_cast<bool>(std::getline(b, lb));
    if (!ha && !hb) break;
    ++line;
    if (ha && hb && la == lb) continue;
    ++shown;
    out << "line " << line << "\n  - " << (ha ? la : "<end>") << "\n  + " << (hb ? lb : "<end>") << "\n";
  }
  return out.str();
}

TEST(ConfigReference, CommittedDocumentsMatchTheTables) {
  for (const std::string path : {"docs/config.md", "docs/elasticity.md"}) {
    const std::string committed = read_file(path);
    ASSERT_FALSE(committed.empty()) << "cannot read " << path << " (tests run from the source directory)";
    ASSERT_NE(committed.find("<!-- generated: "), std::string::npos) << path << " has no generated table";
    const std::string generated = update_config_reference(committed);
    EXPECT_EQ(committed, generated) << path
                                    << " differs from the parameter tables (- committed, + generated):\n"
                                    << line_diff(committed, generated)
                                    << "regenerate with: " << kConfigReferenceCommand;
  }
}

TEST(ConfigReference, EveryTableIsInTheDocuments) {
  const std::string docs = read_file("docs/config.md") + read_file("docs/elasticity.md");
  for (const auto& [id, text] : config_reference_tables())
    EXPECT_NE(docs.find("<!-- generated: " + id + " -->"), std::string::npos) << id;
}

}  // namespace
}  // namespace warpfem::io
