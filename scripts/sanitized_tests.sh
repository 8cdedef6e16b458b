#!/usr/bin/env bash
# Builds warpfem with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/,
# scripts/build.sh --sanitize) and runs the serial test suite under it: every
# test except the 2-rank MPI ones. Any sanitizer report fails its test.
#
#   scripts/sanitized_tests.sh [ctest arguments]    e.g. -L unit, -R test_io
#
# Leak checking is off (detect_leaks=0): Open MPI unloads its components at
# MPI_Finalize with allocations still held, and LeakSanitizer cannot attribute
# (or suppress) leaks of unloaded libraries. scripts/fuzz.sh checks leaks per
# input instead.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --sanitize
# --timeout covers the tests without a limit of their own (the app runs); the test
# executables have 3600 s in the sanitized build (tests/CMakeLists.txt).
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
ctest --test-dir "${WARPFEM_BUILD_DIR:-build-asan}" --output-on-failure -j "${WARPFEM_JOBS:-$(nproc)}" \
  --timeout 3600 -LE mpi "$@"
