#!/usr/bin/env bash
# Random bit flips in a restart file are refused or harmless, never a silent
# change, a crash or a hang (tests/restart_bitflips.py does the trials).
# Usage: restart_bitflips.sh EXE PYTHON COMPARE DECK N TRIALS SEED WORKDIR
# (the dump is of step N; the continuation runs to step 2N)
set -u
exe=$1 py=$2 cmp=$3 deck=$4 n=$5 trials=$6 seed=$7 dir=$8
here=$(cd "$(dirname "$0")" && pwd)
. "$here/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
m=$((2*n)); dump=$(printf 'out/p_restart_%08d.h5' "$n")
derive part1 "$deck" "max_steps = $n, dump_steps = $n" p
"$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
[ -f "$dump" ] || fail "no dump $dump"
# the continuation every trial runs (from r.h5 in its own folder), and its
# result from the unflipped file
derive cont "$deck" "max_steps = $m, restart_from = 'r.h5'" c
mkdir -p ref && cp "$dump" ref/r.h5 && cp cont.nml ref/
(cd ref && "$exe" cont.nml > cont.log 2>&1) || fail "the continuation from the unflipped file failed"
ref=$(cd ref && final_frame c)
[ -n "$ref" ] || fail "no final frame of the reference continuation"
"$py" "$here/restart_bitflips.py" "$exe" "$cmp" "$dump" cont.nml "ref/$ref" "$trials" "$seed"
