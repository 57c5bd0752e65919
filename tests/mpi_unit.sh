#!/bin/bash
# A unit test program on N MPI ranks (oversubscribed; as root, allowed):
# mpi_unit.sh MPIEXEC N PROGRAM [ARGS...]
set -euo pipefail
mpiexec=$1 n=$2
shift 2
root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
OMP_NUM_THREADS=1 exec timeout 120 "$mpiexec" "${root[@]}" --oversubscribe -np "$n" "$@"
