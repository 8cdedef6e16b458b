#pragma once
// Minimal levelled logging. Messages go to stderr (warnings, errors) or
// stdout (info, debug); by default only rank 0 of MPI_COMM_WORLD prints, so a
// run under mpiexec reads like a serial one.

#include <sstream>
#include <string>

namespace warpfem::log {

enum class Level { quiet = 0, error = 1, warning = 2, info = 3, debug = 4 };

void set_level(Level level);
Level level();
/// Parses "quiet|error|warning|info|debug"; throws warpfem::Error otherwise.
Level parse_level(const std::string& name);

void write(Level level, const std::string& message, bool all_ranks = false);

template <typename... Args>
std::string concat(const Args&... args) {
  std::ostringstream os;
  (os << ... << args);
  return os.str();
}

template <typename... Args>
void info(const Args&... args) {
  if (level() >= Level::info) write(Level::info, concat(args...));
}
template <typename... Args>
void debug(const Args&... args) {
  if (level() >= Level::debug) write(Level::debug, concat(args...));
}
template <typename... Args>
void warning(const Args&... args) {
  if (level() >= Level::warning) write(Level::warning, concat(args...));
}
template <typename... Args>
void error(const Args&... args) {
  if (level() >= Level::error) write(Level::error, concat(args...), true);
}

}  // namespace warpfem::log
