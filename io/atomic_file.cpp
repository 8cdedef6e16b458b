#include "io/atomic_file.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

#include "core/error.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

void ensure_directory(const std::string& directory) {
  if (directory.empty()) return;
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec)
    throw Error("cannot create output directory: " + ec.message(),
                {.file = directory, .key_path = "", .hint = "choose a writable /output/directory"});
}

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const fs::path final_path(path);
  ensure_directory(final_path.parent_path().string());
  const fs::path tmp = final_path.parent_path() /
                       ("." + final_path.filename().string() + ".tmp-" + std::to_string(::getpid()));
  try {
    write(tmp.string());
    if (!fs::exists(tmp))
      throw Error("the writer produced no file", {.file = path, .key_path = "", .hint = ""});
    fs::rename(tmp, final_path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void write_text_atomically(const std::string& path, const std::string& content) {
  write_atomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << content;
    out.close();
    if (!out)
      throw Error("cannot write file",
                  {.file = path, .key_path = "", .hint = "check disk space and permissions"});
  });
}

}  // namespace warpfem::io
