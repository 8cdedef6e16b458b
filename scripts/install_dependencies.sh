#!/usr/bin/env bash
# Installs the Debian packages warpfem needs, only those that are missing.
# Idempotent and quick when everything is present. Needs root (or sudo).
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libeigen3-dev            # small dense algebra
  petsc-dev                # Mat/Vec/KSP/SNES/TS/PCMG (pulls in OpenMPI, hypre, MUMPS)
  mpi-default-dev mpi-default-bin
  libvtk9-dev              # VTU/PVTU/PVD writers and readers (never install paraview: it removes libvtk9-dev)
  libpng-dev               # PNG input (reports damaged files)
  libcgal-dev              # exact predicates, constrained Delaunay meshing
  libtet1.5-dev            # TetGen
  nlohmann-json3-dev       # config files
  libmuparser-dev          # expressions in configs
  libgtest-dev libbenchmark-dev
  gnuplot-nox              # PNG plots of convergence studies
  python3                  # tests/apps/mutate_configs.py (mutated-config test)
  clang libclang-rt-dev    # libFuzzer targets and their sanitizers (scripts/fuzz.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "warpfem: all Debian dependencies are installed"
  exit 0
fi

echo "warpfem: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "warpfem: need root to run apt-get; rerun as root or install: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
