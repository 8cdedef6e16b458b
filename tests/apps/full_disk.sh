#!/usr/bin/env bash
# usage: full_disk.sh <limit in KiB> <output file> command args...
# Runs the command once normally (it must write <output file>), then again with every
# file it writes limited to <limit> KiB — a full disk, simulated without root (RLIMIT_FSIZE,
# SIGXFSZ ignored: writes past the limit fail with EFBIG as they would with ENOSPC).
# Passes iff the second run exits non-zero saying so, <output file> is byte for byte the
# first run's, and no temporary file is left beside it. Under mpiexec, start the ranks
# through file_size_limited.sh.
limit="$1"; file="$2"; shift 2
# Open MPI and PMIx back their shared-memory segments with files that would hit the limit
# at start-up: use their file-less alternatives (TCP between ranks, hashed key store).
export PMIX_MCA_gds=hash OMPI_MCA_btl=self,tcp
if ! "$@" > /dev/null 2>&1; then echo "FAIL: the first run failed: $*"; exit 1; fi
if [ ! -s "$file" ]; then echo "FAIL: the first run did not write $file"; exit 1; fi
before=$(sha256sum < "$file")
output=$(ulimit -f "$limit"; trap '' XFSZ; export FULL_DISK_LIMIT_KB="$limit"; "$@" 2>&1); status=$?
echo "$output"
if [ $status -eq 0 ]; then echo "FAIL: the run on a full disk exited 0"; exit 1; fi
if ! grep -qF "check free disk space" <<<"$output"; then echo "FAIL: no message about the failed write"; exit 1; fi
if [ "$(sha256sum < "$file")" != "$before" ]; then echo "FAIL: $file was replaced"; exit 1; fi
leftovers=$(find "$(dirname "$file")" -maxdepth 1 -name '.*.tmp-*')  # not below: tests running beside this one write there
if [ -n "$leftovers" ]; then echo "FAIL: temporary files left: $leftovers"; exit 1; fi
echo "ok: exit $status, $file unchanged"
