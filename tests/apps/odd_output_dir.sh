#!/usr/bin/env bash
# usage: odd_output_dir.sh <warpfem> <study.json> <scratch dir>
# `warpfem study` into a folder whose name holds an apostrophe, a space, ';' and a shell
# command: the plot must be drawn there and nothing in the name may be executed.
app="$1"; config="$2"; scratch="$3"
command -v gnuplot > /dev/null || { echo "gnuplot is not installed: skipped"; exit 77; }
rm -rf "$scratch" && mkdir -p "$scratch" && cd "$scratch" || exit 1
dir="$scratch/John's results; touch INJECTED; echo '"
output=$("$app" study "$config" --output-dir "$dir" 2>&1); status=$?
echo "$output"
if [ $status -ne 0 ]; then echo "FAIL: exit $status"; exit 1; fi
if [ -e INJECTED ]; then echo "FAIL: a command in the folder name was executed"; exit 1; fi
if [ ! -s "$dir/study_errors.png" ]; then echo "FAIL: no plot in $dir"; exit 1; fi
if grep -q "no PNG" <<<"$output"; then echo "FAIL: the plot was lost"; exit 1; fi
echo "ok: plot written, nothing executed"
