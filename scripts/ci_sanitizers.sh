#!/usr/bin/env bash
# The sanitizer and fuzz check sized for a 2-core CI machine (scripts/run_tests.sh
# runs it when CI=true or WARPFEM_SANITIZERS=1): a Clang ASan + UBSan build in
# build-asan-ci/ (WARPFEM_SANITIZER_BUILD_DIR) of only the libFuzzer targets,
# test_core and test_io, at -O1 with line tables (a sixth less compile time
# than -O2 -g; reports keep file and line);
# every fuzz target for 20 s from its committed seeds, with a fixed
# mutation seed so that CI tries a prefix of the same input sequence on every
# machine (a long local run with -seed=1 covers what CI will try); then
# test_core and test_io under the sanitizers. The whole suite under the sanitizers is
# scripts/sanitized_tests.sh; long fuzz runs are scripts/fuzz.sh --runs 1000000.
set -euo pipefail
cd "$(dirname "$0")/.."
export WARPFEM_BUILD_DIR="${WARPFEM_SANITIZER_BUILD_DIR:-build-asan-ci}"
seconds="${WARPFEM_FUZZ_SECONDS:-20}"
export WARPFEM_BUILD_TARGETS="${WARPFEM_BUILD_TARGETS:-test_core test_io fuzz_config fuzz_polygon_file fuzz_gmsh fuzz_png fuzz_make_map}"
fast=(-O1 -gline-tables-only -DNDEBUG)
bash scripts/build.sh --sanitize "-DWARPFEM_TEST_MODULES=core;io" \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=${fast[*]}" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=${fast[*]}"
WARPFEM_FUZZ_ARGS="${WARPFEM_FUZZ_ARGS:--seed=1}" WARPFEM_FUZZ_NO_BUILD=1 bash scripts/fuzz.sh "$seconds"
bash scripts/sanitized_tests.sh -R '^test_(core|io)$'
