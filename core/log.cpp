#include "core/log.hpp"

#include <mpi.h>

#include <atomic>
#include <iostream>

#include "core/error.hpp"

namespace warpfem::log {
namespace {
std::atomic<Level> g_level{Level::info};

int world_rank() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (!initialized || finalized) return 0;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}
}  // namespace

void set_level(Level l) {
  g_level = l;
}
Level level() {
  return g_level;
}

Level parse_level(const std::string& name) {
  if (name == "quiet") return Level::quiet;
  if (name == "error") return Level::error;
  if (name == "warning") return Level::warning;
  if (name == "info") return Level::info;
  if (name == "debug") return Level::debug;
  throw Error("unknown verbosity \"" + name + "\"",
              {.file = "", .key_path = "", .hint = "use one of quiet, error, warning, info, debug"});
}

void write(Level l, const std::string& message, bool all_ranks) {
  const int rank = world_rank();
  if (!all_ranks && rank != 0) return;
  std::string prefix;
  if (l == Level::warning) prefix = "warning: ";
  if (l == Level::error) prefix = "error: ";
  if (l == Level::debug) prefix = "debug: ";
  if (all_ranks && rank != 0) prefix = "[rank " + std::to_string(rank) + "] " + prefix;
  std::ostream& os = (l <= Level::warning) ? std::cerr : std::cout;
  os << prefix << message << std::endl;
}

}  // namespace warpfem::log
