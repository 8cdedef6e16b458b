#!/usr/bin/env bash
# Old against new on a shared, noisy host: runs the same benchmark from two
# build directories in alternating pairs (the order flips every pair, so
# neither binary always gets the warmer or the quieter slot), then prints
# every pair, each binary's median and the median of the new/old ratios.
#
#   bash bench/ab_pairs.sh <pairs> <old build dir> <new build dir> <case>
#
# Cases (the figures BENCHMARKS.md reports):
#   assembly  1.30 M P1 DOFs, warped Poisson assembly, one rank (best of 5 rounds)
#   mg1       1.24 M P1 DOFs, multigrid set-up + solve, one thread
#   mg2       the same on two ranks
# Run from the repository root. Exits non-zero if a run fails.
set -euo pipefail

if [ $# -ne 4 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: bash bench/ab_pairs.sh <pairs> <old build dir> <new build dir> assembly|mg1|mg2" >&2
  exit 2
fi
pairs=$1 old=$2 new=$3 case=$4

mpiexec_args=(-n 2 --oversubscribe)
if [ "$(id -u)" = 0 ]; then mpiexec_args+=(--allow-run-as-root); fi
mg_args=(-order 1 -min_refinements 7 -max_refinements 7 -amg 0 -stream_finest 1)

# One run of build directory $1; prints the case's figure in seconds.
figure() {
  local dir=$1 out
  case "$case" in
    assembly)
      out=$("$dir/bench/fem/bench_assembly" 1140 examples/maps/square_to_gear.json adaptive assembly_only 2>&1) ||
        { echo "ab_pairs: run failed in $dir" >&2; echo "$out" >&2; exit 1; }
      echo "$out" | awk '/^warped +assembly/ { print $3 }' ;;
    mg1 | mg2)
      local cmd=("$dir/bench/multigrid/bench_multigrid_levels" "${mg_args[@]}")
      if [ "$case" = mg2 ]; then cmd=(mpiexec "${mpiexec_args[@]}" "${cmd[@]}"); fi
      out=$(WARPFEM_THREADS=1 "${cmd[@]}" 2>&1) ||
        { echo "ab_pairs: run failed in $dir" >&2; echo "$out" >&2; exit 1; }
      echo "$out" | awk '/MG total set-up/ { gsub(",", "", $9); print $9 }' ;;
    *)
      echo "ab_pairs: unknown case '$case' (assembly, mg1, mg2)" >&2
      exit 2 ;;
  esac
}

olds=() news=() ratios=()
printf '%5s %8s %10s %10s %8s\n' pair load old new new/old
for ((i = 1; i <= pairs; ++i)); do
  load=$(cut -d' ' -f1 /proc/loadavg)
  if ((i % 2)); then a=$(figure "$old"); b=$(figure "$new"); else b=$(figure "$new"); a=$(figure "$old"); fi
  if [ -z "$a" ] || [ -z "$b" ]; then
    echo "ab_pairs: no figure in a run's output (case $case)" >&2
    exit 1
  fi
  r=$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", b / a }')
  olds+=("$a") news+=("$b") ratios+=("$r")
  printf '%5d %8s %10s %10s %8s\n' "$i" "$load" "$a" "$b" "$r"
done

median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "$case: median old $(median "${olds[@]}") s, new $(median "${news[@]}") s, new/old $(median "${ratios[@]}") over $pairs pairs"
