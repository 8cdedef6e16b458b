#include "core/obj_face_groups.hpp"

#include <fstream>
#include <map>
#include <sstream>

#include "core/error.hpp"

namespace warpfem {

ObjFaceGroups read_obj_face_groups(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw Error("cannot open the surface file", {.file = path, .key_path = "", .hint = "check the path"});
  ObjFaceGroups out;
  std::map<std::string, int> id;
  std::string current = "default", line;
  while (std::getline(in, line)) {
    std::istringstream tokens(line);
    std::string statement;
    if (!(tokens >> statement)) continue;
    if (statement == "g") {
      if (!(tokens >> current)) current = "default";
    } else if (statement == "f") {
      const auto [it, added] = id.emplace(current, static_cast<int>(out.names.size()));
      if (added) out.names.push_back(current);
      out.face_group.push_back(it->second);
    }
  }
  if (in.bad())
    throw Error("cannot read the surface file", {.file = path, .key_path = "", .hint = "check the file"});
  return out;
}

}  // namespace warpfem
