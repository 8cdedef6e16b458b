// warpfem-config-reference: regenerates the reference tables of the config
// documentation from the parameter tables (io/config_reference.hpp).
//   warpfem-config-reference FILE        prints FILE with its tables regenerated
//   warpfem-config-reference --write FILE...  rewrites the files in place

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/config_reference.hpp"

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw warpfem::Error("cannot open", {.file = path, .key_path = "", .hint = "check the path"});
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  const bool write = !args.empty() && args[0] == "--write";
  if (args.size() < (write ? 2u : 1u)) {
    std::cerr << "usage: warpfem-config-reference FILE | --write FILE...\n";
    return 2;
  }
  try {
    for (std::size_t i = write ? 1 : 0; i < args.size(); ++i) {
      const std::string updated = warpfem::io::update_config_reference(read(args[i]));
      if (write)
        warpfem::io::write_text_atomically(args[i], updated);
      else
        std::cout << updated;
    }
  } catch (const warpfem::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
