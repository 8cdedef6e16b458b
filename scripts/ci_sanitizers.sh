#!/usr/bin/env bash
# The sanitizer and fuzz check sized for a 2-core CI machine: a Clang
# ASan + UBSan build of the libraries, the fuzz targets and only the io and
# mapping tests (build-asan-ci/), every fuzz target for 20 s, then test_io and
# test_mapping under the sanitizers. The whole suite under the sanitizers is
# scripts/sanitized_tests.sh; long fuzz runs are scripts/fuzz.sh --runs 1000000.
set -euo pipefail
cd "$(dirname "$0")/.."
export WARPFEM_BUILD_DIR="${WARPFEM_BUILD_DIR:-build-asan-ci}"
seconds="${WARPFEM_FUZZ_SECONDS:-20}"
# Only what the checks below run: no apps, benchmarks or multigrid.
export WARPFEM_BUILD_TARGETS="${WARPFEM_BUILD_TARGETS:-test_io test_mapping test_polyhedron_mapping test_map_interpolant fuzz_config fuzz_polygon_file fuzz_gmsh fuzz_png fuzz_make_map}"
bash scripts/build.sh --sanitize "-DWARPFEM_TEST_MODULES=io;mapping"
bash scripts/fuzz.sh "$seconds"
bash scripts/sanitized_tests.sh
