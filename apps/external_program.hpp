#pragma once
// Runs an optional helper program (gnuplot) without a shell: the program is looked up in
// PATH and receives its arguments as a vector, so no character of a path or name is ever
// interpreted (quotes, ';', spaces and '$' reach the program as they are).

#include <string>
#include <vector>

namespace warpfem::apps {

struct ProgramResult {
  bool started = false;  ///< false: not found in PATH or not executable
  bool timed_out = false;
  int exit_code = -1;  ///< exit status if it exited normally, -1 if killed by a signal
  bool succeeded() const { return started && !timed_out && exit_code == 0; }
};

/// Runs `argv[0]` (looked up in PATH) with `argv` as its arguments, stdin from /dev/null,
/// stdout and stderr inherited; waits at most `timeout_seconds`, then kills it.
ProgramResult run_program(const std::vector<std::string>& argv, double timeout_seconds = 120);

}  // namespace warpfem::apps
