#!/usr/bin/env bash
# Builds the libFuzzer targets (Clang, ASan + UBSan: the sanitized build of
# scripts/build.sh --sanitize in build-asan/) and runs each one from the
# committed seeds (tests/fuzz/corpus/<target>) plus what earlier runs found
# (build-asan/fuzz/corpus/<target>). Fails if any target crashes,
# leaks, spends more than 60 s on one input or trips a sanitizer; the input that did it is
# kept in build-asan/fuzz/artifacts/.
#
#   scripts/fuzz.sh [seconds] [target...]   each target for `seconds` (default 60)
#   scripts/fuzz.sh --runs N [target...]    each target for N executions (long runs: N = 1000000)
#
# Targets: config polygon_file gmsh png make_map (default: all).
# WARPFEM_BUILD_DIR (default build-asan) and WARPFEM_JOBS (build jobs) are honoured;
# WARPFEM_FUZZ_ARGS adds libFuzzer flags, e.g. "-max_len=512" (polygon_file's long
# run: unlimited, its inputs grow to 2 kB polygons whose O(n²) checks run at 140/s).
# WARPFEM_FUZZ_NO_BUILD=1 skips the build (runs alongside a build in the same folder).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

limit=(-max_total_time=60)
if [ $# -gt 0 ] && [ "$1" = "--runs" ]; then
  limit=(-runs="$2")
  shift 2
elif [ $# -gt 0 ] && [[ "$1" =~ ^[0-9]+$ ]]; then
  limit=(-max_total_time="$1")
  shift
fi
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(config polygon_file gmsh png make_map)

build_dir="${WARPFEM_BUILD_DIR:-build-asan}"
if ! command -v clang++ >/dev/null 2>&1 && ! command -v clang++-14 >/dev/null 2>&1; then
  echo "fuzz.sh: clang is needed for libFuzzer (apt-get install clang libclang-rt-dev)" >&2
  exit 1
fi
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  WARPFEM_BUILD_DIR="$build_dir" WARPFEM_BUILD_TARGETS="$(printf 'fuzz_%s ' "${targets[@]}")" \
    bash scripts/build.sh --sanitize
fi
jobs="${WARPFEM_JOBS:-$(nproc)}"
if [ -z "${WARPFEM_FUZZ_NO_BUILD:-}" ]; then
  cmake --build "$build_dir" -j "$jobs" --target $(printf 'fuzz_%s ' "${targets[@]}")
fi
read -r -a extra <<<"${WARPFEM_FUZZ_ARGS:-}"

# libFuzzer checks every input for leaks. The check at exit is off: Open MPI's
# components are unloaded at MPI_Finalize with allocations they never free.
export ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="leak_check_at_exit=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
# One thread per target: map evaluation otherwise starts a thread pool per process.
export WARPFEM_THREADS="${WARPFEM_THREADS:-1}"
# The targets write each input to a file; in memory that is ~50 times faster than on disk.
if [ -z "${WARPFEM_FUZZ_TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then WARPFEM_FUZZ_TMPDIR=/dev/shm; fi
export TMPDIR="${WARPFEM_FUZZ_TMPDIR:-${TMPDIR:-/tmp}}"

work="$build_dir/fuzz"
mkdir -p "$work/artifacts"
failed=()
for t in "${targets[@]}"; do
  mkdir -p "$work/corpus/$t"
  log="$work/$t.log"
  echo "fuzz.sh: fuzz_$t (${limit[*]}), log $log"
  # The first corpus folder receives new inputs; the committed seeds stay as they are.
  if "$build_dir/tests/fuzz/fuzz_$t" "${limit[@]}" ${extra[@]+"${extra[@]}"} -timeout=60 -rss_limit_mb=3072 -print_final_stats=1 \
      -artifact_prefix="$work/artifacts/$t-" "$work/corpus/$t" "tests/fuzz/corpus/$t" >"$log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^Done [0-9]+ runs" "$log" | tail -2 | sed "s/^/  /"
  else
    echo "fuzz.sh: fuzz_$t FAILED (see $log):" >&2
    grep -E "ERROR|runtime error|deadly signal|timeout|Test unit written|^Base64:" "$log" | head -8 | sed "s/^/  /" >&2
    # The stack frames below libFuzzer's own, so that a CI log alone shows where it failed.
    grep -E "^ +#[0-9]+ " "$log" | grep -v -E "fuzzer::|__sanitizer|libc\.so|_start|__libc" | head -12 | sed "s/^/  /" >&2
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz.sh: failed targets: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz.sh: no crash in ${targets[*]}"
