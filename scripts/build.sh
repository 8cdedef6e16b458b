#!/usr/bin/env bash
# Configures (once) and builds warpfem in build/ (Release, -Wall -Wextra).
# Extra arguments are passed to the CMake configure step, e.g. -DWARPFEM_NATIVE=ON.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${WARPFEM_BUILD_DIR:-build}"
jobs="${WARPFEM_JOBS:-$(nproc)}"
if [ ! -f "$build_dir/CMakeCache.txt" ] || [ $# -gt 0 ]; then
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
fi
cmake --build "$build_dir" -j "$jobs"
