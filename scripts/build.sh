#!/usr/bin/env bash
# Configures (once) and builds warpfem in build/ (Release, -Wall -Wextra).
# Extra arguments are passed to the CMake configure step, e.g. -DWARPFEM_NATIVE=ON.
#
#   scripts/build.sh --sanitize [cmake args]   AddressSanitizer + UndefinedBehaviorSanitizer
#       build (RelWithDebInfo, no benchmarks) in build-asan/; run its tests with
#       scripts/sanitized_tests.sh, which sets the sanitizer options.
set -euo pipefail
cd "$(dirname "$0")/.."
default_dir=build
if [ "${1:-}" = "--sanitize" ]; then
  shift
  default_dir=build-asan
  set -- -DWARPFEM_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWARPFEM_BUILD_BENCH=OFF "$@"
fi
build_dir="${WARPFEM_BUILD_DIR:-$default_dir}"
jobs="${WARPFEM_JOBS:-$(nproc)}"
if [ ! -f "$build_dir/CMakeCache.txt" ] || [ $# -gt 0 ]; then
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
fi
cmake --build "$build_dir" -j "$jobs" ${WARPFEM_BUILD_TARGETS:+--target $WARPFEM_BUILD_TARGETS}
