#!/usr/bin/env bash
# A straight run to step 2N equals a run to step N with a dump plus a restart
# from that dump to step 2N, bit for bit (same build, same thread count).
# Usage: restart_invariance.sh EXE PYTHON COMPARE DECK N WORKDIR [FILE...]
# FILEs (e.g. a deck's file of points) are copied into WORKDIR, where the
# derived decks run.
set -u
exe=$1 py=$2 cmp=$3 deck=$4 n=$5 dir=$6
shift 6
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"
for extra in "$@"; do cp "$extra" "$dir"/ || fail "cannot copy $extra"; done
cd "$dir" || exit 1
m=$((2*n)); dump=$(printf 'out/split_restart_%08d.h5' "$n")
derive straight "$deck" "max_steps = $m" straight
derive part1 "$deck" "max_steps = $n, dump_steps = $n" split
derive part2 "$deck" "max_steps = $m, restart_from = '$dump'" split
"$exe" straight.nml > straight.log 2>&1 || fail "straight run failed (see $dir/straight.log)"
"$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
[ -f "$dump" ] || fail "no dump $dump"
"$exe" part2.nml > part2.log 2>&1 || { cat part2.log; fail "restart failed"; }
grep -q "restarted from $dump at step $n" part2.log || fail "the log does not report the restart"
"$py" "$cmp" "$(final_frame straight)" "$(final_frame split)" --exact
