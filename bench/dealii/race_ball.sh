#!/usr/bin/env bash
# warpfem against deal.II on the unit ball, −Δu = 1, u = 0 on the sphere, about
# 1 M unknowns, end to end (mesh and DOFs, geometry, assembly of every level,
# multigrid set-up, CG to 1e-8), one thread each: warpfem's Q1 hexahedra and
# P1 tetrahedra on the box [-1,1]³ mapped onto the ball (bench_poisson_3d
# -domain ball, -n 13 -refinements 3: 1,157,625 DOFs) and deal.II's Q1 on
# hyper_ball_balanced refined 5 times (1,061,121 DOFs). The runs of a round
# rotate their order every round, so that no program always gets the same
# slot on a shared host. Prints every run (wall and process CPU seconds of the
# timed phases, CG iterations, peak RSS, L2 error against the exact solution),
# then the medians and the deal.II/warpfem ratios of the medians.
#
#   bash bench/dealii/race_ball.sh <rounds> <build dir>
#
# Needs a build with -DWARPFEM_BENCH_DEALII=ON. Exits non-zero if a run fails.
set -euo pipefail

if [ $# -ne 2 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: bash bench/dealii/race_ball.sh <rounds> <build dir>" >&2
  exit 2
fi
rounds=$1 build=$2
warpfem=$build/bench/multigrid/bench_poisson_3d
dealii=$build/bench/dealii/dealii_poisson_ball
for exe in "$warpfem" "$dealii"; do
  [ -x "$exe" ] || { echo "race_ball: $exe not found (configure with -DWARPFEM_BENCH_DEALII=ON)" >&2; exit 2; }
done

# One run of program $1 (q1, p1 or dealii); prints "name wall cpu its rss_mb dofs l2".
run() {
  local out
  case "$1" in
    q1 | p1)
      local type=hexahedron
      if [ "$1" = p1 ]; then type=tetrahedron; fi
      out=$(WARPFEM_THREADS=1 OMP_NUM_THREADS=1 "$warpfem" -domain ball -type "$type" -n 13 -refinements 3 -geometry streamed \
              -peers gmg 2>&1) || { echo "race_ball: $1 failed" >&2; echo "$out" >&2; exit 1; }
      echo "$out" | awk -v name="warpfem_$1" '
        /^ball :/ { l2 = $5; sub(",", "", l2) }
        / levels, / { for (i = 1; i <= NF; ++i) if ($i == "DOFs,") dofs = $(i-1) }
        /^GMG  : hierarchy/ { for (i = 1; i <= NF; ++i) { if ($i == "its;") its = $(i-1); if ($i == "total") wall = $(i+1) } }
        /^GMG  : CPU set-up/ { for (i = 1; i <= NF; ++i) if ($i == "=") cpu = $(i+1) }
        /^peak RSS/ { rss = $3 }
        END { print name, wall, cpu, its, rss, dofs, l2 }' ;;
    dealii)
      out=$(DEAL_II_NUM_THREADS=1 "$dealii" 5 balanced 2>&1) || { echo "race_ball: deal.II failed" >&2; echo "$out" >&2; exit 1; }
      echo "$out" | awk '
        /^  total/ { wall = $2; cpu = $5 }
        /^deal.II/ { for (i = 1; i <= NF; ++i) { if ($i == "DOFs,") dofs = $(i-1); if ($i == "CG") its = $(i-1); if ($i == "RSS") rss = $(i+1) } }
        /^L2 error/ { l2 = $3; sub(",", "", l2) }
        END { print "deal.II", wall, cpu, its, rss, dofs, l2 }' ;;
  esac
}

programs=(q1 dealii p1)
results=$(mktemp)
trap 'rm -f "$results"' EXIT
printf "%-12s %9s %9s %4s %8s %9s %11s\n" run wall_s cpu_s its rss_MB dofs L2_error
for ((r = 0; r < rounds; ++r)); do
  for ((k = 0; k < ${#programs[@]}; ++k)); do
    line=$(run "${programs[(k + r) % ${#programs[@]}]}")
    echo "$line" >> "$results"
    echo "$line" | awk '{ printf "%-12s %9.3f %9.3f %4d %8.0f %9d %11s\n", $1, $2, $3, $4, $5, $6, $7 }'
  done
done
echo "medians over $rounds rounds (deal.II / warpfem: of the medians; per DOF: scaled by DOFs)"
awk '
  { wall[$1] = wall[$1] " " $2; cpu[$1] = cpu[$1] " " $3; rss[$1] = rss[$1] " " $5; dofs[$1] = $6 }
  function median(list,   a, n, i, j, t) {
    n = split(list, a, " ")
    for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] + 0 < a[i] + 0) { t = a[i]; a[i] = a[j]; a[j] = t }
    return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
  }
  END {
    dw = median(wall["deal.II"]); dc = median(cpu["deal.II"])
    for (name in wall) {
      w = median(wall[name]); c = median(cpu[name]); m = median(rss[name])
      printf "%-12s wall %7.3f s, CPU %7.3f s, peak RSS %5.0f MB (%4.0f bytes/DOF)", name, w, c, m,
             m * 1048576 / dofs[name]
      if (name != "deal.II")
        printf "; deal.II/%s: wall %.2f, CPU %.2f, CPU per DOF %.2f", name, dw / w, dc / c,
               (dc / dofs["deal.II"]) / (c / dofs[name])
      printf "\n"
    }
  }' "$results"
