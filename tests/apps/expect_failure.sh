#!/usr/bin/env bash
# usage: expect_failure.sh "<expected text>" command args...
# Passes iff the command exits non-zero and its output contains the expected text.
expected="$1"; shift
output=$("$@" 2>&1); status=$?
echo "$output"
if [ $status -eq 0 ]; then echo "FAIL: command succeeded but should have failed"; exit 1; fi
if ! grep -qF -- "$expected" <<<"$output"; then echo "FAIL: output lacks: $expected"; exit 1; fi
echo "ok: exit $status with the expected message"
