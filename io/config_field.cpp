#include "io/config_field.hpp"

#include <regex>

namespace warpfem::io {

std::string json_pointer(const std::string& field) {
  std::string out = "/" + field;
  for (char& c : out)
    if (c == '.') c = '/';
  return out;
}

namespace {

/// Parameter ids quoted in a hint ("raise solver.max_iterations") read as pointers there.
std::string pointers_in_hint(const std::string& hint) {
  static const std::regex id(
      R"(\b((?:map|mesh|problem|solver|output|limits|time|load_stepping)(?:\.[a-z_]+)+)\b)");
  std::string out;
  auto last = hint.cbegin();
  for (std::sregex_iterator it(hint.begin(), hint.end(), id), end; it != end; ++it) {
    out.append(last, hint.cbegin() + it->position(0));
    out += json_pointer(it->str(1));
    last = hint.cbegin() + it->position(0) + it->length(0);
  }
  out.append(last, hint.cend());
  return out;
}

}  // namespace

bool is_parameter_id(const std::string& key_path) {
  return !key_path.empty() && key_path[0] != '/';
}

Error with_json_pointer(const Error& e) {
  if (!is_parameter_id(e.context().key_path)) return e;
  Error::Context c = e.context();
  c.key_path = json_pointer(c.key_path);
  c.hint = pointers_in_hint(c.hint);
  return Error(e.message(), c);
}

Error in_config(const Error& e, const std::string& file) {
  if (e.context().key_path.empty()) return e;
  return with_json_pointer(e).in_file(file);
}

}  // namespace warpfem::io
