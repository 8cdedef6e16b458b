#!/usr/bin/env bash
# Configures (once) and builds warpfem in build/ (Release, -Wall -Wextra).
# Extra arguments are passed to the CMake configure step, e.g. -DWARPFEM_NATIVE=ON.
#
#   scripts/build.sh --sanitize [cmake args]
#       AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/
#       (RelWithDebInfo, no benchmarks): the library, the tests and, with Clang,
#       the libFuzzer targets. Uses Clang when installed (else the default
#       compiler, without fuzz targets). Run its tests with scripts/sanitized_tests.sh
#       and the fuzz targets with scripts/fuzz.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
default_dir=build
if [ "${1:-}" = "--sanitize" ]; then
  shift
  default_dir=build-asan
  sanitize=(-DWARPFEM_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWARPFEM_BUILD_BENCH=OFF)
  clang_cxx=$(command -v clang++ || command -v clang++-14 || true)
  clang_c=$(command -v clang || command -v clang-14 || true)
  if [ -n "$clang_cxx" ] && [ -n "$clang_c" ]; then
    sanitize+=(-DCMAKE_CXX_COMPILER="$clang_cxx" -DCMAKE_C_COMPILER="$clang_c" -DWARPFEM_BUILD_FUZZ=ON)
  fi
  command -v ccache >/dev/null 2>&1 && sanitize+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  set -- "${sanitize[@]}" "$@"
fi
build_dir="${WARPFEM_BUILD_DIR:-$default_dir}"
jobs="${WARPFEM_JOBS:-$(nproc)}"
if [ ! -f "$build_dir/CMakeCache.txt" ] || [ $# -gt 0 ]; then
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
fi
# WARPFEM_BUILD_TARGETS="a b": build only these targets.
cmake --build "$build_dir" -j "$jobs" ${WARPFEM_BUILD_TARGETS:+--target $WARPFEM_BUILD_TARGETS}
