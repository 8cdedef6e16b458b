#pragma once
// Validated access to one JSON object of a config file.
//
// Every read records the key as used; finish() then rejects keys nobody read
// (typos such as "refinement" for "refinements" are errors, not silently
// ignored). Every error names the file and the JSON pointer of the field:
//   run.json: /mesh/refinements: expected a non-negative integer, got "two"

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"

namespace warpfem::io {

class ConfigNode {
 public:
  /// `json` must outlive the node. `path` is the JSON pointer of `json` ("" for the root).
  ConfigNode(const nlohmann::json& json, std::string file, std::string path = "");

  /// Loads and parses a JSON file; syntax errors name the line and column,
  /// duplicate keys the key and its line; nesting deeper than 64 levels is refused.
  static nlohmann::json parse_file(const std::string& file);

  /// True if `key` is present and not null (also marks it as a known key).
  bool has(const std::string& key) const;
  /// The object stored at `key` (must be a JSON object).
  ConfigNode child(const std::string& key) const;
  /// The raw JSON stored at `key` (marks it used, no type check).
  const nlohmann::json& raw(const std::string& key) const;

  bool get_bool(const std::string& key, bool fallback) const;
  long get_int(const std::string& key, long fallback, long min = std::numeric_limits<long>::min(),
               long max = std::numeric_limits<long>::max()) const;
  double get_double(const std::string& key, double fallback,
                    double min = -std::numeric_limits<double>::infinity(),
                    double max = std::numeric_limits<double>::infinity()) const;
  /// A number > 0 (and <= max).
  double get_positive(const std::string& key, double fallback,
                      double max = std::numeric_limits<double>::infinity()) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  /// A string that must be one of `choices`.
  std::string get_choice(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& choices) const;
  /// A number or an expression string (returned as text, e.g. "2*pi").
  std::string get_expression(const std::string& key, const std::string& fallback) const;
  std::vector<double> get_doubles(const std::string& key) const;
  /// An array of [x, y] pairs.
  std::vector<Point<2>> get_points(const std::string& key) const;

  /// Throws if the object holds a key none of the getters asked for.
  void finish() const;

  /// An error located at `key` of this node (key may be empty for the node itself).
  Error error(const std::string& key, const std::string& message, const std::string& hint = "") const;

  const std::string& file() const { return file_; }
  std::string path_of(const std::string& key) const { return key.empty() ? path_ : path_ + "/" + key; }

 private:
  const nlohmann::json* find(const std::string& key) const;
  const nlohmann::json& json_;
  std::string file_;
  std::string path_;
  mutable std::set<std::string> used_;
};

/// The candidate nearest to `word` within `max_distance` edits ("" if none): for "did you mean".
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates,
                          std::size_t max_distance = 2);

/// Short rendering of a JSON value for messages ("two" -> "\"two\"", long arrays truncated).
std::string json_excerpt(const nlohmann::json& value);

}  // namespace warpfem::io
