#!/usr/bin/env bash
# The warped run end to end against deal.II, about 1.3 M unknowns, one thread
# each: `warpfem run` on the curved 192-vertex gear (examples/poisson_gear_curved.json:
# composite mean value map, every level warped) with P1 and P2, the same P1
# problem with PETSc GAMG and hypre BoomerAMG on warpfem's finest matrix
# ("solver": {"pc_type": ...}), the identity-map L-shape at about the same
# DOFs (the price of the map), and deal.II 9.4 solving −Δu = 1 on the unit
# disk (curved by its manifold, MappingQ of the element's degree, matrix-based
# geometric multigrid; bench/dealii/poisson_ball.cc) with Q1 and Q2. Every
# program writes its solution (VTU) as part of its run. The runs of a round
# rotate their order every round, so that no program always gets the same
# slot on a shared host.
#
#   bash bench/dealii/race_gear.sh <rounds> <build dir> [programs...]
#
# programs: gear_p1 gear_p2 lshape_p1 gear_p1_gamg gear_p1_hypre dealii_q1
# dealii_q2 (default: all; the deal.II ones need a build with
# -DWARPFEM_BENCH_DEALII=ON). Prints every run (wall and process CPU seconds of
# the whole process, of the output alone, CG iterations, peak RSS, DOFs), then
# medians and ratios against deal.II of the same degree. Exits non-zero if a
# run fails.
#
# Every run starts after a pause of RACE_PAUSE seconds (default 8). On a VM
# whose balloon driver reports free memory to the host, memory freed a moment
# ago is cheap to touch again and memory free for a few seconds is not (a
# host fault per 2 MiB block): without the pause a program's set-up depends on
# how its predecessor freed its memory (1.4 against 2.7 s for the P2 gear).
# With it every program starts cold, as a job on a shared machine does.
set -euo pipefail

if [ $# -lt 2 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: bash bench/dealii/race_gear.sh <rounds> <build dir> [programs...]" >&2
  exit 2
fi
rounds=$1 build=$2
shift 2
programs=("$@")
if [ ${#programs[@]} -eq 0 ]; then
  programs=(gear_p1 dealii_q1 lshape_p1 gear_p2 dealii_q2 gear_p1_gamg gear_p1_hypre)
fi
root=$(cd "$(dirname "$0")/../.." && pwd)
warpfem=$build/apps/warpfem
dealii=$build/bench/dealii/dealii_poisson_ball
[ -x "$warpfem" ] || { echo "race_gear: $warpfem not found" >&2; exit 2; }
for p in "${programs[@]}"; do
  case "$p" in
    dealii_*) [ -x "$dealii" ] || { echo "race_gear: $dealii not found (configure with -DWARPFEM_BENCH_DEALII=ON)" >&2; exit 2; } ;;
    gear_p1 | gear_p2 | lshape_p1 | gear_p1_gamg | gear_p1_hypre) ;;
    *) echo "race_gear: unknown program $p" >&2; exit 2 ;;
  esac
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Configs: the gear with h0 = 0.165, P1 refined 6 times and P2 5 times
# (1.31 M DOFs each), CG to 1e-8; the L-shape with the gear's source and
# boundary values, h0 chosen for about the same P1 DOFs.
gear() {  # order refinements [pc_type]
  jq --arg out "$work/out" --argjson order "$1" --argjson ref "$2" --arg pc "${3:-mg}" '
    .problem.order = $order | .mesh.max_edge_length = 0.165 | .mesh.refinements = $ref
    | .solver.rtol = 1e-8 | .output.directory = $out | .verbosity = "info"
    | if $pc != "mg" then .solver = {"rtol": 1e-8, "pc_type": $pc} else . end' \
    "$root/examples/poisson_gear_curved.json"
}
gear 1 6 > "$work/gear_p1.json"
gear 2 5 > "$work/gear_p2.json"
gear 1 6 gamg > "$work/gear_p1_gamg.json"
gear 1 6 hypre > "$work/gear_p1_hypre.json"
jq --arg out "$work/out" '
  .mesh = {"max_edge_length": 0.155, "refinements": 6} | .problem.source = "1"
  | .problem.dirichlet = [{"edges": "all", "value": 0}] | del(.problem.exact_solution)
  | .solver = {"rtol": 1e-8} | .output.directory = $out' \
  "$root/examples/poisson_lshape.json" > "$work/lshape_p1.json"

# One run; prints "name wall cpu output_wall its rss_mb dofs".
run() {
  local name=$1 out timing
  timing=$work/time.txt
  case "$name" in
    dealii_q1 | dealii_q2)
      local degree=1 refinements=9
      if [ "$name" = dealii_q2 ]; then degree=2 refinements=8; fi
      out=$(DEAL_II_NUM_THREADS=1 OMP_NUM_THREADS=1 /usr/bin/time -f "%e %U %S %M" -o "$timing" \
              "$dealii" "$refinements" plain 2 "$degree" "$work/out_dealii.vtu" 2>&1) ||
        { echo "race_gear: $name failed" >&2; echo "$out" >&2; exit 1; }
      echo "$out" | awk -v name="$name" -v t="$(cat "$timing")" '
        /^  output/ { output = $3 }
        /^deal.II/ { for (i = 1; i <= NF; ++i) { if ($i == "DOFs,") dofs = $(i-1); if ($i == "CG") its = $(i-1) } }
        END { split(t, a, " "); print name, a[1], a[2] + a[3], output, its, a[4] / 1024, dofs }' ;;
    *)
      out=$(WARPFEM_THREADS=1 OMP_NUM_THREADS=1 /usr/bin/time -f "%e %U %S %M" -o "$timing" \
              "$warpfem" run "$work/$name.json" 2>&1) ||
        { echo "race_gear: $name failed" >&2; echo "$out" >&2; exit 1; }
      echo "$out" | awk -v name="$name" -v t="$(cat "$timing")" '
        /^wrote / { s = $0; sub(/^[^(]*\(/, "", s); sub(/ s.*/, "", s); output = s }
        /DOFs on/ { for (i = 1; i <= NF; ++i) if ($i == "DOFs") dofs = $(i-1) }
        /^solved with/ { for (i = 1; i <= NF; ++i) if ($i == "iterations,") its = $(i-1) }
        END { split(t, a, " "); print name, a[1], a[2] + a[3], output, its, a[4] / 1024, dofs }' ;;
  esac
}

pause=${RACE_PAUSE:-8}
[[ "$pause" =~ ^[0-9]+$ ]] || { echo "race_gear: RACE_PAUSE must be a whole number of seconds" >&2; exit 2; }
results=$work/results.txt
printf "%-14s %8s %8s %9s %4s %7s %8s\n" run wall_s cpu_s output_s its rss_MB dofs
for ((r = 0; r < rounds; ++r)); do
  for ((k = 0; k < ${#programs[@]}; ++k)); do
    sleep "$pause"
    line=$(run "${programs[(k + r) % ${#programs[@]}]}")
    echo "$line" >> "$results"
    echo "$line" | awk '{ printf "%-14s %8.2f %8.2f %9.2f %4d %7.0f %8d\n", $1, $2, $3, $4, $5, $6, $7 }'
  done
done
echo "medians over $rounds rounds; 'before output' = whole process minus the output's wall time;"
echo "ratios: program / deal.II of the same degree (P1 vs Q1, P2 vs Q2), of the medians"
awk '
  { wall[$1] = wall[$1] " " $2; cpu[$1] = cpu[$1] " " $3; outw[$1] = outw[$1] " " $4
    pre[$1] = pre[$1] " " ($2 - $4); rss[$1] = rss[$1] " " $6; dofs[$1] = $7; its[$1] = $5 }
  function median(list,   a, n, i, j, t) {
    n = split(list, a, " ")
    for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] + 0 < a[i] + 0) { t = a[i]; a[i] = a[j]; a[j] = t }
    return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
  }
  END {
    for (name in wall) {
      w = median(wall[name]); c = median(cpu[name]); o = median(outw[name]); p = median(pre[name])
      m = median(rss[name])
      printf "%-14s %8d DOFs, %3d its: wall %7.2f s (before output %7.2f, output %6.2f = %2.0f %%), CPU %7.2f s, peak RSS %5.0f MB (%4.0f B/DOF)",
             name, dofs[name], its[name], w, p, o, 100 * o / w, c, m, m * 1048576 / dofs[name]
      peer = (name ~ /p2|q2/) ? "dealii_q2" : "dealii_q1"
      if (name !~ /^dealii/ && (peer in wall))
        printf "; / %s: wall %.2f, before output %.2f, CPU %.2f", peer, w / median(wall[peer]),
               p / median(pre[peer]), c / median(cpu[peer])
      printf "\n"
    }
  }' "$results" | sort
