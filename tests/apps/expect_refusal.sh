#!/usr/bin/env bash
# usage: expect_refusal.sh <output path> "<expected text>" command args...
# expect_failure.sh, and the command must leave nothing at <output path>
# (removed first, so a file from an earlier run cannot hide a write).
out="$1"; shift
rm -rf -- "$out"
"$(dirname "$0")/expect_failure.sh" "$@" || exit 1
if [ -e "$out" ]; then echo "FAIL: the refused command wrote $out"; exit 1; fi
echo "ok: nothing written at $out"
