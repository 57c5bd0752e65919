#!/usr/bin/env bash
# 1 and 2 OpenMP threads give bit-for-bit identical results: every cell and
# node update is independent of the thread partition, the only reduction in a
# step is a minimum (exact in any order) and the conservation sums are serial.
# Usage: thread_invariance.sh EXE PYTHON COMPARE DECK N WORKDIR
set -u
exe=$1 py=$2 cmp=$3 deck=$4 n=$5 dir=$6
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
derive one "$deck" "max_steps = $n" one
derive two "$deck" "max_steps = $n" two
OMP_NUM_THREADS=1 "$exe" one.nml > one.log 2>&1 || fail "1-thread run failed"
OMP_NUM_THREADS=2 "$exe" two.nml > two.log 2>&1 || fail "2-thread run failed"
"$py" "$cmp" out/one_00001.h5 out/two_00001.h5 --exact
