#!/usr/bin/env bash
# One command from a fresh Debian machine to a tested build: installs what is
# missing, builds, and runs the whole test suite (serial and 2-rank MPI tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_dependencies.sh
bash scripts/build.sh
export OMPI_MCA_rmaps_base_oversubscribe=1
ctest --test-dir "${WARPFEM_BUILD_DIR:-build}" --output-on-failure -j "${WARPFEM_JOBS:-$(nproc)}" --timeout 600
# WARPFEM_SANITIZERS=1 adds the sanitizer and fuzz subset (Clang ASan + UBSan build in
# build-asan-ci/, every fuzz target 20 s, io and mapping tests). Off by default, also in CI:
# its from-scratch sanitized build alone exceeds CI's time budget on a 2-core machine
# (docs/reliability.md, "Sanitizers").
if [ "${WARPFEM_SANITIZERS:-0}" = 1 ]; then
  WARPFEM_BUILD_DIR=build-asan-ci bash scripts/ci_sanitizers.sh
fi
