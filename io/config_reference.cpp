#include "io/config_reference.hpp"

#include <charconv>
#include <cmath>

#include "core/error.hpp"
#include "fem/hierarchy/mesh_parameters.hpp"
#include "io/elasticity_parameters.hpp"
#include "io/run_parameters.hpp"
#include "mapping/map_parameters.hpp"
#include "multigrid/multigrid_parameters.hpp"

namespace warpfem::io {
namespace {

/// Shortest text that reads back as `v`, with a plain exponent ("1e-4", not "1e-04").
std::string number_text(double v) {
  char buffer[32];
  std::string s(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
  const auto e = s.find('e');
  if (e != std::string::npos) {
    std::size_t digits = e + 1 + (s[e + 1] == '-' || s[e + 1] == '+' ? 1 : 0);
    if (s[e + 1] == '+') s.erase(e + 1, 1), --digits;
    while (digits + 1 < s.size() && s[digits] == '0') s.erase(digits, 1);
  }
  return s;
}

std::string quoted_list(const std::vector<std::string>& choices) {
  std::string out;
  for (const auto& c : choices) out += (out.empty() ? "`\"" : ", `\"") + c + "\"`";
  return out;
}

template <class S>
std::string type_text(const Parameter<S>& p) {
  if (!p.type_text.empty()) return p.type_text;
  const bool low = std::isfinite(p.min), high = std::isfinite(p.max);
  const auto bound_text = [&p](double v) {
    return p.kind == ParameterKind::integer ? std::to_string(static_cast<long>(v)) : number_text(v);
  };
  const std::string range = low && high ? " in [" + bound_text(p.min) + ", " + bound_text(p.max) + "]"
                            : low       ? " ≥ " + bound_text(p.min)
                            : high      ? " ≤ " + bound_text(p.max)
                                        : "";
  switch (p.kind) {
    case ParameterKind::boolean: return "boolean";
    case ParameterKind::integer: return "integer" + range;
    case ParameterKind::number: return "number" + range;
    case ParameterKind::positive: return "number > 0";
    case ParameterKind::text: return "string";
    case ParameterKind::choice: return quoted_list(p.choices);
    case ParameterKind::expression: return "number or expression";
    case ParameterKind::petsc_ksp: return "string (PETSc KSP type)";
    case ParameterKind::petsc_pc: return "string (PETSc PC type)";
    case ParameterKind::other: break;
  }
  return "";
}

template <class S>
std::string default_text(const Parameter<S>& p, const S& defaults) {
  if (!p.default_text.empty()) return p.default_text;
  const ParameterValue v = p.get(defaults);
  if (const bool* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (const long* i = std::get_if<long>(&v)) return std::to_string(*i);
  if (const double* d = std::get_if<double>(&v)) return number_text(*d);
  const std::string& s = std::get<std::string>(v);
  if (s.empty()) return p.kind == ParameterKind::text ? "`\"\"`" : "—";
  if (p.kind == ParameterKind::expression) return s;
  return "`\"" + s + "\"`";
}

template <class S>
std::string markdown(const ParameterTable<S>& table) {
  const S defaults{};
  std::string out = "| key | type | default | meaning |\n|---|---|---|---|\n";
  for (const auto& p : table.entries())
    out +=
        "| `" + p.name + "` | " + type_text(p) + " | " + default_text(p, defaults) + " | " + p.doc + " |\n";
  return out;
}

const std::string kBegin = "<!-- generated: ";
const std::string kEnd = "<!-- end generated: ";

}  // namespace

std::vector<std::pair<std::string, std::string>> config_reference_tables() {
  return {{"top_level", markdown(top_level_parameters())},
          {"map", markdown(mapping::map_parameters())},
          {"mesh", markdown(fem::mesh_parameters())},
          {"problem", markdown(poisson_parameters())},
          {"solver", markdown(solver_parameters())},
          {"solver.multigrid", markdown(multigrid::multigrid_parameters())},
          {"output", markdown(output_parameters())},
          {"limits", markdown(limits_parameters())},
          {"elasticity.problem", markdown(elasticity_parameters())},
          {"elasticity.material", markdown(material_parameters())},
          {"elasticity.load_stepping", markdown(load_stepping_parameters())},
          {"elasticity.time", markdown(time_parameters())},
          {"elasticity.solver", markdown(newton_parameters())},
          {"elasticity.output", markdown(elasticity_output_parameters())}};
}

std::string update_config_reference(const std::string& document) {
  const auto tables = config_reference_tables();
  std::string out;
  std::size_t pos = 0;
  for (std::size_t begin; (begin = document.find(kBegin, pos)) != std::string::npos;) {
    const std::size_t id_end = document.find(" -->", begin);
    if (id_end == std::string::npos) throw Error("unclosed marker \"" + kBegin + "\"");
    const std::string id = document.substr(begin + kBegin.size(), id_end - begin - kBegin.size());
    const std::string end_marker = kEnd + id + " -->";
    const std::size_t end = document.find(end_marker, id_end);
    if (end == std::string::npos) throw Error("no \"" + end_marker + "\" after the table \"" + id + "\"");
    const std::string* table = nullptr;
    for (const auto& [name, text] : tables)
      if (name == id) table = &text;
    if (!table) throw Error("no generated table \"" + id + "\"");
    out.append(document, pos, id_end + 4 - pos).append("\n").append(*table);
    pos = end;
  }
  return out.append(document, pos);
}

}  // namespace warpfem::io
