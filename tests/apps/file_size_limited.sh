#!/usr/bin/env bash
# usage: file_size_limited.sh command args...
# For full_disk.sh under mpiexec: the MPI launcher resets SIGXFSZ to its default (which
# kills the process) and may change limits, so each rank re-applies them: SIGXFSZ ignored,
# and files limited to $FULL_DISK_LIMIT_KB KiB when that is set.
trap '' XFSZ
if [ -n "$FULL_DISK_LIMIT_KB" ]; then ulimit -f "$FULL_DISK_LIMIT_KB"; fi
exec "$@"
