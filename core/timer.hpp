#pragma once
// Wall-clock timing: a stopwatch and a scoped timer that logs on exit.

#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>

#include "core/log.hpp"

namespace warpfem {

/// "0.012 s", "3.4 ms"-free fixed formatting used in all progress logs.
inline std::string format_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f s", s);
  return buf;
}

/// CPU seconds of the whole process (every thread) since it started: for
/// comparing stages on a shared host, where wall time includes stolen time.
inline double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

class Stopwatch {
 public:
  Stopwatch() : start_(clock::now()) {}
  void reset() { start_ = clock::now(); }
  /// Seconds since construction or the last reset().
  double seconds() const { return std::chrono::duration<double>(clock::now() - start_).count(); }

 private:
  using clock = std::chrono::steady_clock;
  clock::time_point start_;
};

/// Logs "<label>: <seconds> s" at debug level when it goes out of scope.
class ScopedTimer {
 public:
  explicit ScopedTimer(std::string label) : label_(std::move(label)) {}
  ~ScopedTimer() { log::debug(label_, ": ", watch_.seconds(), " s"); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  std::string label_;
  Stopwatch watch_;
};

}  // namespace warpfem
