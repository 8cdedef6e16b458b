#!/usr/bin/env bash
# The two-rank speed-up of multigrid set-up + solve, measured the way
# BENCHMARKS.md reports it: one-thread and two-rank runs alternated, so that
# both members of a pair see the same state of a noisy shared host, and the
# median of the pair ratios.
#
#   bash bench/multigrid/two_rank_ratio.sh [pairs] [extra bench options...]
#
# Defaults: 10 pairs of the headline problem (1.24 M P1 DOFs, curved disk,
# finest geometry streamed). Run from the repository root after building
# (build/bench/multigrid/bench_multigrid_levels). Prints every pair and the
# medians; exits non-zero if a run fails.
set -euo pipefail

pairs=${1:-10}
shift || true
if ! [[ "$pairs" =~ ^[1-9][0-9]*$ ]]; then
  echo "two_rank_ratio: the number of pairs must be a positive integer, got '$pairs'" >&2
  exit 2
fi
bench=${BENCH:-build/bench/multigrid/bench_multigrid_levels}
args=(-order 1 -min_refinements 7 -max_refinements 7 -amg 0 -stream_finest 1 "$@")
mpiexec_args=(-n 2)
if [ "$(id -u)" = 0 ]; then mpiexec_args+=(--allow-run-as-root); fi
mpiexec_args+=(--oversubscribe)

if [ ! -x "$bench" ]; then
  echo "two_rank_ratio: $bench not found; build first (cmake --build build)" >&2
  exit 1
fi

# "set-up + solve" of one run (seconds), from the bench's summary line.
total_of() {
  local out
  out=$("$@" 2>&1) || { echo "two_rank_ratio: run failed: $*" >&2; echo "$out" >&2; exit 1; }
  local total
  total=$(echo "$out" | awk '/MG total set-up/ { gsub(",", "", $9); print $9 }')
  if [ -z "$total" ]; then
    echo "two_rank_ratio: no 'MG total set-up' line in the output of: $*" >&2
    exit 1
  fi
  echo "$total"
}

ones=() twos=() ratios=()
printf '%5s %12s %12s %8s\n' pair "1 thread" "2 ranks" ratio
for ((i = 1; i <= pairs; ++i)); do
  one=$(WARPFEM_THREADS=1 total_of "$bench" "${args[@]}")
  two=$(total_of mpiexec "${mpiexec_args[@]}" "$bench" "${args[@]}")
  ratio=$(awk -v a="$one" -v b="$two" 'BEGIN { printf "%.3f", a / b }')
  ones+=("$one") twos+=("$two") ratios+=("$ratio")
  printf '%5d %12s %12s %8s\n' "$i" "$one" "$two" "$ratio"
done

median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
at_least=$(printf '%s\n' "${ratios[@]}" | awk '$1 >= 1.6 { n++ } END { print n + 0 }')
echo "median: 1 thread $(median "${ones[@]}") s, 2 ranks $(median "${twos[@]}") s," \
  "ratio $(median "${ratios[@]}") (${at_least} of ${pairs} pairs >= 1.6)"
