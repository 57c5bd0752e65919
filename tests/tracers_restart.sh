#!/usr/bin/env bash
# Tracers and the maximum pressure across a restart: a straight run, and
# the same run split by a dump at step N (its first part running 15 steps
# past the dump, whose tracer rows the restart drops), leave the same
# tracer file byte for byte and final frames bit for bit (max_pressure
# included: compare_frames.py --exact, and h5diff of the whole frame but
# the deck). Optionally on MPI ranks: the first part on P ranks and the
# second on one process (a dump written by the ranks together continues on
# one), compared with a straight run on one process.
# Usage: tracers_restart.sh EXE PYTHON COMPARE DECK N WORKDIR [MPIEXEC P]
set -u
exe=$1 py=$2 cmp=$3 deck=$4 n=$5 dir=$6 mpiexec=${7:-} np=${8:-1}
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
export OMP_NUM_THREADS=1
# make NEW NAME RUN_VARS: the deck with output dir 'out', name NAME (the rest
# of &output kept: fields, tracers, gauge_dt) and RUN_VARS added to &run
make() {
  sed -e "s|^\(&run .*\)/ *\$|\1 $3 /|" -e "s|^\(&output \)dir = '[^']*'|\1dir = 'out', name = '$2'|" "$deck" > "$1.nml"
  grep -q "name = '$2'" "$1.nml" || fail "could not derive $1.nml from $deck"
}
make straight straight ""
make part1 split ", max_steps = $((n + 15)), dump_steps = $n"
make part2 split ", restart_from = 'out/split_restart_$(printf %08d "$n").h5'"
"$exe" straight.nml > straight.log 2>&1 || fail "straight run failed (see $dir/straight.log)"
if [ -n "$mpiexec" ]; then
  root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
  timeout 600 "$mpiexec" "${root[@]}" --oversubscribe -np "$np" "$exe" part1.nml > part1.log 2>&1 || \
    { tail part1.log; fail "first part on $np ranks failed"; }
  grep -q "^run: $np MPI ranks" part1.log || fail "the first part did not run on $np ranks"
else
  "$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
fi
"$exe" part2.nml > part2.log 2>&1 || { tail part2.log; fail "restart failed"; }
grep -q "restarted from out/split_restart_" part2.log || fail "the log does not report the restart"
rows=$(grep -vc '^#' out/straight_tracers.txt)
[ "$rows" -ge 5 ] || fail "only $rows tracer rows"
cmp out/straight_tracers.txt out/split_tracers.txt || { diff out/straight_tracers.txt out/split_tracers.txt | head -4; \
  fail "the split run's tracer file differs"; }
echo "ok: tracer files ($rows rows) identical"
last() { ls out/"$1"_[0-9][0-9][0-9][0-9][0-9].h5 | sort | tail -1; }
"$py" "$cmp" "$(last straight)" "$(last split)" --exact || fail "final frames differ"
h5diff --exclude-path /deck "$(last straight)" "$(last split)" > h5diff.txt || { head -5 h5diff.txt; \
  fail "final frame files differ (h5diff)"; }
echo "PASS: split tracer file and final frame (max_pressure included) equal the straight run's"
