#!/usr/bin/env bash
# One command from a fresh Debian machine to a result: installs what is
# missing, builds, and runs the default example (examples/default.json, or the
# config given as first argument). Prints where the output is.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_dependencies.sh
bash scripts/build.sh
config="${1:-examples/default.json}"
./build/apps/warpfem run "$config"
echo
echo "Open the .vtu/.pvtu file named above in ParaView (File > Open, then Apply)."
