#include "fuzz_input.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "core/environment.hpp"
#include "core/log.hpp"

namespace warpfem::fuzz {
namespace fs = std::filesystem;
namespace {

struct Workspace {
  fs::path folder;
  Workspace() {
    const char* tmp = std::getenv("TMPDIR");
    folder = fs::path(tmp && *tmp ? tmp : "/tmp") / ("warpfem-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(folder);
  }
  ~Workspace() {
    std::error_code ec;
    fs::remove_all(folder, ec);
  }
};

Workspace& workspace() {
  static Workspace w;
  return w;
}

}  // namespace

void start_environment() {
  static char name[] = "warpfem-fuzz";
  static char* argv_storage[] = {name, nullptr};
  static int argc = 1;
  static char** argv = argv_storage;
  static const std::unique_ptr<Environment> environment = std::make_unique<Environment>(argc, argv);
  log::set_level(log::Level::quiet);
}

std::string write_input(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const fs::path path = workspace().folder / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::perror(path.c_str());
    std::abort();
  }
  return path.string();
}

}  // namespace warpfem::fuzz
