#!/usr/bin/env bash
# &run wall_time_limit: the run writes a restart and stops with status 3 and
# a message saying how to continue; continuing from that file works.
# The deck is run on CELLS^3 cells, enough to outlast LIMIT seconds.
# Usage: restart_wall_time.sh EXE DECK LIMIT CELLS WORKDIR
set -u
exe=$1 deck=$2 limit=$3 cells=$4 dir=$5
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
# on failure, show the end of every log for diagnosis
trap 'rc=$?; if [ $rc -ne 0 ]; then for f in *.log; do echo "== $f"; tail -8 "$f"; done; fi' EXIT
derive limited "$deck" "wall_time_limit = $limit" wt
sed -i -e "s/ni = [0-9]*, nj = [0-9]*, nk = [0-9]*/ni = $cells, nj = $cells, nk = $cells/" limited.nml
"$exe" limited.nml > limited.log 2>&1; rc=$?
[ "$rc" -eq 3 ] || { tail -5 limited.log; fail "exit status $rc, expected 3"; }
file=$(sed -n "s/.*restart_from = '\([^']*\)'.*/\1/p" limited.log | tail -1)
[ -n "$file" ] && [ -f "$file" ] || { tail -5 limited.log; fail "no 'restart_from' advice naming an existing file"; }
step=$(sed -n 's/.*reached at step \([0-9]*\),.*/\1/p' limited.log)
echo "stopped at step $step, restart file $file"
derive more "$deck" "max_steps = $((step + 3)), restart_from = '$file'" wt
sed -i -e "s/ni = [0-9]*, nj = [0-9]*, nk = [0-9]*/ni = $cells, nj = $cells, nk = $cells/" more.nml
"$exe" more.nml > more.log 2>&1 || { tail more.log; fail "continuing failed"; }
grep -q "restarted from $file at step $step" more.log || fail "restart not reported"
grep -q "after $((step + 3)) steps" more.log || fail "did not continue to step $((step + 3))"
echo "PASS restart_wall_time"
