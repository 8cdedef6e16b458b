#!/usr/bin/env bash
# The warped run end to end on one rank (one thread) against two ranks
# (`mpiexec -n 2`, one thread each): `warpfem run` on the curved 192-vertex
# gear, P1 refined 6 times (1,312,769 DOFs), CG to 1e-8, VTU output. Runs
# alternate (the order flips every pair) and each starts after a pause of
# PAIR_PAUSE seconds (default 8), so both members of a pair see the same state
# of a noisy shared host; prints every pair and the medians of the pair ratios,
# of the run's own total (its "total" line) and of the process wall including
# mpiexec's start.
#
#   bash bench/two_rank_run.sh [pairs=6] [build dir=build]
#
# Run from the repository root after building. Exits non-zero if a run fails.
set -euo pipefail

pairs=${1:-6}
build=${2:-build}
if ! [[ "$pairs" =~ ^[1-9][0-9]*$ ]]; then
  echo "two_rank_run: the number of pairs must be a positive integer, got '$pairs'" >&2
  exit 2
fi
pause=${PAIR_PAUSE:-8}
warpfem=$build/apps/warpfem
[ -x "$warpfem" ] || { echo "two_rank_run: $warpfem not found; build first" >&2; exit 2; }
command -v jq > /dev/null || { echo "two_rank_run: needs jq" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
mpiexec_args=(-n 2 --oversubscribe)
if [ "$(id -u)" = 0 ]; then mpiexec_args+=(--allow-run-as-root); fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
jq --arg out "$work/out" '.problem.order = 1 | .mesh.max_edge_length = 0.165 | .mesh.refinements = 6
  | .solver.rtol = 1e-8 | .output.directory = $out' "$root/examples/poisson_gear_curved.json" > "$work/gear_p1.json"

# One run: prints "total wall" (seconds).
run() {
  local out
  out=$( { WARPFEM_THREADS=1 /usr/bin/time -f "WALL %e" "$@" run "$work/gear_p1.json"; } 2>&1) || {
    echo "two_rank_run: run failed: $*" >&2
    echo "$out" >&2
    exit 1
  }
  echo "$(echo "$out" | awk '/^total/ { print $2 }') $(echo "$out" | awk '/^WALL/ { print $2 }')"
}

median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
totals=() walls=()
printf '%5s %22s %22s %8s %8s\n' pair "1 rank: total, wall" "2 ranks: total, wall" total wall
for ((i = 1; i <= pairs; ++i)); do
  order=(one two)
  if ((i % 2 == 0)); then order=(two one); fi
  for who in "${order[@]}"; do
    sleep "$pause"
    if [ "$who" = one ]; then
      read -r one_total one_wall < <(run "$warpfem")
    else
      read -r two_total two_wall < <(run mpiexec "${mpiexec_args[@]}" "$warpfem")
    fi
  done
  rt=$(awk -v a="$one_total" -v b="$two_total" 'BEGIN { printf "%.3f", a / b }')
  rw=$(awk -v a="$one_wall" -v b="$two_wall" 'BEGIN { printf "%.3f", a / b }')
  totals+=("$rt") walls+=("$rw")
  printf '%5d %10s %11s %10s %11s %8s %8s\n' "$i" "$one_total" "$one_wall" "$two_total" "$two_wall" "$rt" "$rw"
done
echo "median ratio: run total $(median "${totals[@]}"), process wall $(median "${walls[@]}") (two ranks against one)"
