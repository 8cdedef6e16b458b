#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <system_error>

#include "core/error.hpp"
#include "core/log.hpp"
#include "io/early_writeback.hpp"

namespace warpfem::io {
namespace fs = std::filesystem;

namespace {

const char* const kTemporaryMarker = ".tmp-";
const char* const kWriteHint =
    "check free disk space and permissions; the previous file, if any, is unchanged";

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof buffer - 1) != 0 || buffer[0] == '\0') return "localhost";
  std::string host(buffer);
  // Only characters that are safe in a file name and cannot be mistaken for the separator.
  for (char& c : host)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_') c = '_';
  return host;
}

[[noreturn]] void throw_system_error(const std::string& what, int error, const std::string& path) {
  throw Error(what + ": " + std::strerror(error), {.file = path, .key_path = "", .hint = kWriteHint});
}

/// True if `name` is `.<something>.tmp-<this host>-<pid>` of a process that no longer exists.
bool is_stale_temporary(const std::string& name, const std::string& host) {
  if (name.empty() || name[0] != '.') return false;
  const auto marker = name.rfind(kTemporaryMarker);
  if (marker == std::string::npos) return false;
  const std::string tag = name.substr(marker + std::strlen(kTemporaryMarker));
  const auto dash = tag.rfind('-');
  if (dash == std::string::npos || tag.substr(0, dash) != host) return false;
  const std::string digits = tag.substr(dash + 1);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos)
    return false;
  const pid_t pid = static_cast<pid_t>(std::stol(digits));
  if (pid <= 0 || pid == ::getpid()) return false;
  // ESRCH: no such process. EPERM means it exists (another user's): keep its files.
  return ::kill(pid, 0) != 0 && errno == ESRCH;
}

}  // namespace

// Cleans each output directory once per process: a run writes many files into the same one.
void prepare_output_directory(const std::string& directory) {
  ensure_directory(directory);
  static std::mutex mutex;
  static std::set<std::string> done;
  std::error_code ec;
  const std::string key = fs::absolute(directory.empty() ? "." : directory, ec).lexically_normal().string();
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (!done.insert(key).second) return;
  }
  const int removed = remove_stale_temporaries(directory);
  if (removed > 0)
    log::info("removed ", removed, " leftover temporary file(s) of interrupted runs in ",
              directory.empty() ? "." : directory);
}

std::string process_tag() {
  static const std::string tag = host_name() + "-" + std::to_string(::getpid());
  return tag;
}

std::string temporary_path(const std::string& directory, const std::string& filename,
                           const std::string& tag) {
  return (fs::path(directory) / ("." + filename + kTemporaryMarker + tag)).string();
}

void ensure_directory(const std::string& directory) {
  if (directory.empty()) return;
  std::error_code ec;
  // A file (not a folder) at that path, or on the way to it, is the common case: say so.
  for (fs::path p = directory; !p.empty(); p = p.parent_path()) {
    if (fs::exists(p, ec) && !fs::is_directory(p, ec))
      throw Error(
          "cannot create output directory: " + p.string() + " is a file",
          {.file = directory, .key_path = "", .hint = "choose another /output/directory or move the file"});
    if (p == p.parent_path()) break;
  }
  fs::create_directories(directory, ec);
  if (ec || !fs::is_directory(directory)) {
    const std::string reason = ec ? ec.message() : "it is not a folder";
    throw Error("cannot create output directory: " + reason,
                {.file = directory, .key_path = "", .hint = "choose a writable /output/directory"});
  }
}

void sync_file(const std::string& path, const std::string& reported_path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw_system_error("cannot open the written file again", errno, reported_path);
  int error = ::fsync(fd) != 0 ? errno : 0;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) throw_system_error("cannot flush the file to disk", error, reported_path);
}

void rename_into_place(const std::string& from, const std::string& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec)
    throw Error("cannot move the finished file into place: " + ec.message(),
                {.file = to, .key_path = "", .hint = kWriteHint});
  // Make the rename itself durable. Best effort: some file systems refuse fsync on a
  // directory (EINVAL), and the file is complete and in place either way.
  const std::string dir = fs::path(to).parent_path().string();
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

int remove_stale_temporaries(const std::string& directory) {
  const std::string host = host_name();
  std::error_code ec;
  fs::directory_iterator it(directory.empty() ? "." : directory, ec);
  int removed = 0;
  for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
    if (!is_stale_temporary(it->path().filename().string(), host)) continue;
    std::error_code remove_ec;
    if (fs::remove_all(it->path(), remove_ec) > 0 && !remove_ec) ++removed;
  }
  return removed;
}

void write_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const fs::path final_path(path);
  const std::string directory = final_path.parent_path().string();
  prepare_output_directory(directory);
  const std::string tmp = temporary_path(directory, final_path.filename().string());
  try {
    {
      const EarlyWriteback writeback(tmp);
      write(tmp);
    }
    std::error_code ec;
    if (!fs::is_regular_file(tmp, ec))
      throw Error("the writer produced no file", {.file = path, .key_path = "", .hint = kWriteHint});
    sync_file(tmp, path);
    rename_into_place(tmp, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void write_text_atomically(const std::string& path, const std::string& content) {
  write_atomically(path, [&](const std::string& tmp) {
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw_system_error("cannot create the file", errno, path);
    const char* data = content.data();
    std::size_t left = content.size();
    int error = 0;
    while (left > 0) {
      const ssize_t n = ::write(fd, data, left);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        error = n < 0 ? errno : EIO;
        break;
      }
      data += n;
      left -= static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) throw_system_error("cannot write the file", error, path);
  });
}

}  // namespace warpfem::io
