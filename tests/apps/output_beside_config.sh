#!/usr/bin/env bash
# usage: output_beside_config.sh <warpfem> <scratch dir>
# A relative "output.directory" starts at the config file's directory: a run started
# from another working directory writes next to its config and leaves the working
# directory untouched; the log names the directory.
app="$1"; scratch="$2"
rm -rf "$scratch" && mkdir -p "$scratch/project/configs" "$scratch/elsewhere" || exit 1
cat > "$scratch/project/configs/run.json" <<'JSON'
{
  "map": { "type": "identity", "source": [[0, 0], [1, 0], [1, 1], [0, 1]] },
  "mesh": { "type": "structured", "cells": 2 },
  "problem": { "source": 1, "dirichlet": [{ "edges": "all", "value": 0 }] },
  "output": { "directory": "results", "name": "u" }
}
JSON
cd "$scratch/elsewhere" || exit 1
output=$("$app" run ../project/configs/run.json 2>&1); status=$?
echo "$output"
if [ $status -ne 0 ]; then echo "FAIL: exit $status"; exit 1; fi
if [ ! -s "$scratch/project/configs/results/u.vtu" ]; then echo "FAIL: no results/u.vtu beside the config"; exit 1; fi
if [ -n "$(ls -A "$scratch/elsewhere")" ]; then echo "FAIL: files in the working directory:"; ls -A; exit 1; fi
if ! grep -q "output directory ../project/configs/results" <<<"$output"; then
  echo "FAIL: the log does not name the output directory"; exit 1
fi
echo "ok: output written beside the config, working directory untouched"
