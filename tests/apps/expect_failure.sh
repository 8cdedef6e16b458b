#!/usr/bin/env bash
# usage: expect_failure.sh [--once] "<expected text>" command args...
# Passes iff the command exits non-zero and its output contains the expected text
# (with --once: exactly once, as under mpiexec where every rank might print it), and no
# message carries a doubled "error: error:" prefix.
once=0
if [ "$1" = "--once" ]; then once=1; shift; fi
expected="$1"; shift
output=$("$@" 2>&1); status=$?
echo "$output"
if [ $status -eq 0 ]; then echo "FAIL: command succeeded but should have failed"; exit 1; fi
count=$(grep -cF -- "$expected" <<<"$output")
if [ "$count" -eq 0 ]; then echo "FAIL: output lacks: $expected"; exit 1; fi
if [ $once -eq 1 ] && [ "$count" -ne 1 ]; then echo "FAIL: printed $count times: $expected"; exit 1; fi
if grep -q "error: error:" <<<"$output"; then echo "FAIL: doubled \"error: error:\" prefix"; exit 1; fi
echo "ok: exit $status with the expected message"
