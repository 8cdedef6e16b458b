#!/usr/bin/env bash
# One command from a fresh Debian machine to a tested build: installs what is
# missing, builds, and runs the whole test suite (serial and 2-rank MPI tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_dependencies.sh
bash scripts/build.sh
export OMPI_MCA_rmaps_base_oversubscribe=1
ctest --test-dir "${WARPFEM_BUILD_DIR:-build}" --output-on-failure -j "${WARPFEM_JOBS:-$(nproc)}" --timeout 600
# The sanitizer and fuzz subset (scripts/ci_sanitizers.sh: Clang ASan + UBSan build in
# build-asan-ci/, every fuzz target 20 s, test_core and test_io sanitized) runs in CI
# (CI=true) and with WARPFEM_SANITIZERS=1; WARPFEM_SANITIZERS=0 skips it.
sanitizers="${WARPFEM_SANITIZERS:-}"
if [ -z "$sanitizers" ] && [ "${CI:-}" = true ]; then sanitizers=1; fi
if [ "$sanitizers" = 1 ]; then
  bash scripts/ci_sanitizers.sh
fi
