#!/usr/bin/env bash
# One command from a fresh Debian machine to a tested build: installs what is
# missing, builds, and runs the whole test suite (serial and 2-rank MPI tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_dependencies.sh
bash scripts/build.sh
export OMPI_MCA_rmaps_base_oversubscribe=1
ctest --test-dir "${WARPFEM_BUILD_DIR:-build}" --output-on-failure -j "${WARPFEM_JOBS:-$(nproc)}" --timeout 600
