#include "io/config_node.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace warpfem::io {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string type_name(const nlohmann::json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) return "an array";
  return "an object";
}

}  // namespace

std::string json_excerpt(const nlohmann::json& value) {
  std::string s = value.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

ConfigNode::ConfigNode(const nlohmann::json& json, std::string file, std::string path)
    : json_(json), file_(std::move(file)), path_(std::move(path)) {
  if (!json_.is_object())
    throw Error("expected an object ({ ... }), got " + type_name(json_) + " " + json_excerpt(json_),
                {.file = file_, .key_path = path_.empty() ? "/" : path_, .hint = ""});
}

nlohmann::json ConfigNode::parse_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error("cannot open config file", {.file = file, .key_path = "", .hint = "check the path"});
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  try {
    return nlohmann::json::parse(text, nullptr, true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    const std::size_t pos = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + pos, '\n'));
    const std::size_t line_start = text.rfind('\n', pos == 0 ? 0 : pos - 1);
    const std::size_t column = pos - (line_start == std::string::npos ? 0 : line_start + 1) + 1;
    std::string what = e.what();
    const auto colon = what.find("error: ");
    if (colon != std::string::npos) what = what.substr(colon + 7);
    throw Error(
        "invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + what,
        {.file = file, .key_path = "", .hint = "fix the JSON syntax (missing comma, quote or bracket?)"});
  }
}

const nlohmann::json* ConfigNode::find(const std::string& key) const {
  used_.insert(key);
  auto it = json_.find(key);
  if (it == json_.end() || it->is_null()) return nullptr;
  return &*it;
}

bool ConfigNode::has(const std::string& key) const {
  used_.insert(key);
  return json_.contains(key) && !json_.at(key).is_null();
}

Error ConfigNode::error(const std::string& key, const std::string& message, const std::string& hint) const {
  return Error(message, {.file = file_, .key_path = path_of(key).empty() ? "/" : path_of(key), .hint = hint});
}

ConfigNode ConfigNode::child(const std::string& key) const {
  const nlohmann::json* v = find(key);
  static const nlohmann::json empty = nlohmann::json::object();
  if (!v) return ConfigNode(empty, file_, path_of(key));
  if (!v->is_object())
    throw error(key, "expected an object ({ ... }), got " + type_name(*v) + " " + json_excerpt(*v));
  return ConfigNode(*v, file_, path_of(key));
}

const nlohmann::json& ConfigNode::raw(const std::string& key) const {
  const nlohmann::json* v = find(key);
  if (!v) throw error(key, "missing required field");
  return *v;
}

bool ConfigNode::get_bool(const std::string& key, bool fallback) const {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_boolean()) throw error(key, "expected true or false, got " + json_excerpt(*v));
  return v->get<bool>();
}

long ConfigNode::get_int(const std::string& key, long fallback, long min, long max) const {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  std::string expected = "an integer";
  if (min == 0 && max == std::numeric_limits<long>::max()) expected = "a non-negative integer";
  if (min == 1 && max == std::numeric_limits<long>::max()) expected = "a positive integer";
  if (min != std::numeric_limits<long>::min() && max != std::numeric_limits<long>::max())
    expected = "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  const bool integral =
      v->is_number_integer() || (v->is_number_float() && std::floor(v->get<double>()) == v->get<double>() &&
                                 std::abs(v->get<double>()) < 1e15);
  if (!integral) throw error(key, "expected " + expected + ", got " + json_excerpt(*v));
  const long value = v->is_number_integer() ? v->get<long>() : static_cast<long>(v->get<double>());
  if (value < min || value > max) throw error(key, "expected " + expected + ", got " + json_excerpt(*v));
  return value;
}

double ConfigNode::get_double(const std::string& key, double fallback, double min, double max) const {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_number()) throw error(key, "expected a number, got " + json_excerpt(*v));
  const double value = v->get<double>();
  if (!(value >= min && value <= max)) {
    std::string range = "in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
    if (max == std::numeric_limits<double>::infinity()) range = ">= " + std::to_string(min);
    throw error(key, "expected a number " + range + ", got " + json_excerpt(*v));
  }
  return value;
}

std::string ConfigNode::get_string(const std::string& key, const std::string& fallback) const {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_string()) throw error(key, "expected a string, got " + json_excerpt(*v));
  return v->get<std::string>();
}

std::string ConfigNode::get_choice(const std::string& key, const std::string& fallback,
                                   const std::vector<std::string>& choices) const {
  const std::string value = get_string(key, fallback);
  if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + ("\"" + c + "\"");
    throw error(key, "unknown value \"" + value + "\"", "use one of " + list);
  }
  return value;
}

std::string ConfigNode::get_expression(const std::string& key, const std::string& fallback) const {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (v->is_number()) {
    std::ostringstream os;
    os.precision(17);
    os << v->get<double>();
    return os.str();
  }
  if (!v->is_string()) throw error(key, "expected a number or an expression string, got " + json_excerpt(*v));
  return v->get<std::string>();
}

std::vector<double> ConfigNode::get_doubles(const std::string& key) const {
  const nlohmann::json* v = find(key);
  if (!v) return {};
  if (!v->is_array()) throw error(key, "expected an array of numbers, got " + json_excerpt(*v));
  std::vector<double> out;
  for (std::size_t i = 0; i < v->size(); ++i) {
    if (!(*v)[i].is_number())
      throw error(key + "/" + std::to_string(i), "expected a number, got " + json_excerpt((*v)[i]));
    out.push_back((*v)[i].get<double>());
  }
  return out;
}

std::vector<Point<2>> ConfigNode::get_points(const std::string& key) const {
  const nlohmann::json* v = find(key);
  if (!v) return {};
  if (!v->is_array()) throw error(key, "expected an array of [x, y] pairs, got " + json_excerpt(*v));
  std::vector<Point<2>> out;
  for (std::size_t i = 0; i < v->size(); ++i) {
    const auto& p = (*v)[i];
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw error(key + "/" + std::to_string(i), "expected a pair [x, y] of numbers, got " + json_excerpt(p));
    out.emplace_back(p[0].get<double>(), p[1].get<double>());
  }
  return out;
}

void ConfigNode::finish() const {
  for (auto it = json_.begin(); it != json_.end(); ++it) {
    if (used_.count(it.key())) continue;
    std::string best;
    std::size_t best_distance = 3;
    for (const auto& u : used_) {
      const std::size_t d = edit_distance(it.key(), u);
      if (d < best_distance) best = u, best_distance = d;
    }
    std::string known;
    for (const auto& u : used_) known += (known.empty() ? "" : ", ") + u;
    throw error(it.key(), "unknown key \"" + it.key() + "\"",
                best.empty() ? "remove it; keys allowed here: " + known : "did you mean \"" + best + "\"?");
  }
}

}  // namespace warpfem::io
