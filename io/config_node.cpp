#include "io/config_node.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>

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

/// The shortest text that reads back as `v` (std::to_string prints 1e-300 as 0.000000).
std::string exact_number(double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

std::string type_name(const nlohmann::json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) return "an array";
  return "an object";
}

constexpr std::size_t kExcerptLength = 60;

/// Appends `value` to `out` until it holds more than kExcerptLength
/// characters; recursion stops at a small depth, so deeply nested documents
/// cannot exhaust the stack (nlohmann's dump() recurses without a limit).
void append_excerpt(const nlohmann::json& value, std::string& out, int depth) {
  if (out.size() > kExcerptLength) return;
  if (!value.is_structured()) {
    out += value.dump();
    return;
  }
  const bool array = value.is_array();
  out += array ? '[' : '{';
  if (depth >= 8 && !value.empty()) {
    out += "...";
  } else {
    bool first = true;
    for (auto it = value.begin(); it != value.end() && out.size() <= kExcerptLength; ++it) {
      if (!first) out += ',';
      first = false;
      if (!array) out += nlohmann::json(it.key()).dump() + ':';
      append_excerpt(*it, out, depth + 1);
    }
  }
  out += array ? ']' : '}';
}

/// The 1-based line of the `index`-th object key (0-based, in document
/// order) of a JSON text with // and /* */ comments.
std::size_t line_of_key(const std::string& text, std::size_t index) {
  std::size_t line = 1, keys = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      for (i += 2; i + 1 < text.size() && !(text[i] == '*' && text[i + 1] == '/'); ++i)
        if (text[i] == '\n') ++line;
      ++i;
    } else if (c == '"') {
      const std::size_t start_line = line;
      for (++i; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\')
          ++i;
        else if (text[i] == '\n')
          ++line;
      }
      std::size_t j = i + 1;  // a string followed by ':' is a key
      while (j < text.size() && std::isspace(static_cast<unsigned char>(text[j]))) ++j;
      if (j < text.size() && text[j] == ':' && keys++ == index) return start_line;
    }
  }
  return line;
}

/// Line and column (1-based) of the first occurrence of the number `token` in
/// a JSON text outside strings and comments; {0, 0} if there is none.
std::pair<std::size_t, std::size_t> locate_number(const std::string& text, const std::string& token) {
  const auto number_char = [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E' || c == '+' ||
           c == '-';
  };
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      line_start = i + 1;
    } else if (c == '"') {
      for (++i; i < text.size() && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      for (i += 2; i + 1 < text.size() && !(text[i] == '*' && text[i + 1] == '/'); ++i)
        if (text[i] == '\n') ++line, line_start = i + 1;
      ++i;
    } else if (text.compare(i, token.size(), token) == 0 && (i == 0 || !number_char(text[i - 1])) &&
               (i + token.size() == text.size() || !number_char(text[i + token.size()]))) {
      return {line, i - line_start + 1};
    }
  }
  return {0, 0};
}

/// Limits of parse_file: configs nest a few levels; much deeper documents are
/// refused before they are built.
constexpr int kMaxJsonDepth = 64;

}  // namespace

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates,
                          std::size_t max_distance) {
  std::string best;
  std::size_t best_distance = max_distance + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance) best = c, best_distance = d;
  }
  return best;
}

std::string json_excerpt(const nlohmann::json& value) {
  std::string s;
  append_excerpt(value, s, 0);
  if (s.size() > kExcerptLength) s = s.substr(0, kExcerptLength - 3) + "...";
  return s;
}

ConfigNode::ConfigNode(const nlohmann::json& json, std::string file, std::string path)
    : json_(json), file_(std::move(file)), path_(std::move(path)) {
  if (!json_.is_object())
    throw Error("expected an object ({ ... }), got " + type_name(json_) + " " + json_excerpt(json_),
                {.file = file_, .key_path = path_.empty() ? "/" : path_, .hint = ""});
}

nlohmann::json ConfigNode::parse_file(const std::string& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw Error("is a directory, not a config file",
                {.file = file, .key_path = "", .hint = "give the path of a .json file"});
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw Error("cannot open config file: " + std::generic_category().message(errno),
                {.file = file, .key_path = "", .hint = "check the path and its permissions"});
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad())
    throw Error("cannot read config file", {.file = file, .key_path = "", .hint = "check the file"});
  const std::string text = buffer.str();
  // Duplicate keys: nlohmann keeps the last one silently, so the callback
  // tracks the keys of every open object (keys[d]: the object at depth d).
  std::vector<std::set<std::string>> keys(1);
  std::size_t key_count = 0;
  const auto callback = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if ((event == Event::object_start || event == Event::array_start) && depth >= kMaxJsonDepth)
      throw Error(
          "the document nests arrays and objects deeper than " + std::to_string(kMaxJsonDepth) + " levels",
          {.file = file, .key_path = "", .hint = "a config nests a few levels; check the file"});
    if (event == Event::object_start) {
      keys.resize(static_cast<std::size_t>(depth) + 2);
      keys[static_cast<std::size_t>(depth) + 1].clear();
    } else if (event == Event::key) {
      const std::string key = parsed.get<std::string>();
      if (!keys[static_cast<std::size_t>(depth)].insert(key).second)
        throw Error("duplicate key \"" + key + "\" at line " + std::to_string(line_of_key(text, key_count)) +
                        " (JSON keeps only one of them)",
                    {.file = file, .key_path = "", .hint = "remove one of the two \"" + key + "\" entries"});
      ++key_count;
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, callback, true, /*ignore_comments=*/true);
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
  } catch (const nlohmann::json::exception& e) {
    // Numbers beyond double range (1e999) and similar: invalid input, not an internal error.
    // nlohmann reports no position for these; the quoted token locates them.
    std::string what = e.what();
    if (const auto bracket = what.find("] "); bracket != std::string::npos) what = what.substr(bracket + 2);
    std::string where;
    if (const auto open = what.find('\''), close = what.rfind('\'');
        open != std::string::npos && close > open + 1) {
      if (const auto [line, column] = locate_number(text, what.substr(open + 1, close - open - 1)); line > 0)
        where = " at line " + std::to_string(line) + ", column " + std::to_string(column);
    }
    throw Error("invalid JSON" + where + ": " + what,
                {.file = file, .key_path = "", .hint = "numbers must be finite doubles (|x| < 1.8e308)"});
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
    std::string range = "in [" + exact_number(min) + ", " + exact_number(max) + "]";
    if (max == std::numeric_limits<double>::infinity()) range = ">= " + exact_number(min);
    throw error(key, "expected a number " + range + ", got " + json_excerpt(*v));
  }
  return value;
}

double ConfigNode::get_positive(const std::string& key, double fallback, double max) const {
  const nlohmann::json* v = find(key);
  if (!v) return fallback;
  if (!v->is_number()) throw error(key, "expected a number, got " + json_excerpt(*v));
  const double value = v->get<double>();
  if (!(value > 0 && value <= max))
    throw error(key,
                "expected a number > 0" +
                    (max == std::numeric_limits<double>::infinity() ? "" : " and <= " + exact_number(max)) +
                    ", got " + json_excerpt(*v));
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
