#!/usr/bin/env bash
# Tracked particles (&output track): a straight run's tracks file against
# its final frame (tests/check_tracks.py: same ids, x, v, stress, energy to
# the printed digits, time column exact), its time column equal to the gauge
# file's, and a run split by a restart (the first part running on past the
# dump) leaving the same tracks file byte for byte.
# Usage: particles_track.sh EXE PYTHON CHECK DECK N WORKDIR
set -u
exe=$1 py=$2 check=$3 deck=$4 n=$5 dir=$6
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
# make NEW NAME RUN_VARS: DECK with &output dir 'out' and name NAME, RUN_VARS added to &run
make() {
  sed -e "s|^\(&run .*\)/ *\$|\1 $3 /|" -e "s|^\(&output\) dir = '[^']*'|\1 dir = 'out', name = '$2'|" \
      "$deck" > "$1.nml"
  grep -q "name = '$2'" "$1.nml" || fail "could not derive $1.nml from $deck"
}
make straight straight ""
make part1 split ", max_steps = $((n + 15)), dump_steps = $n"
make part2 split ", restart_from = 'out/split_restart_$(printf %08d "$n").h5'"
"$exe" straight.nml > straight.log 2>&1 || fail "straight run failed (see $dir/straight.log)"
"$py" "$check" out/straight_tracks.txt "$(ls out/straight_[0-9]*.h5 | sort | tail -1)" || fail "tracks against the frame"
grep -v '^#' out/straight_tracks.txt | awk '{print $1}' > tracks_time.txt
grep -v '^#' out/straight_gauges.txt | awk '{print $1}' > gauges_time.txt
cmp tracks_time.txt gauges_time.txt || fail "the time columns of the tracks and gauge files differ"
echo "time column: $(wc -l < tracks_time.txt) rows, equal to the gauge file's"
"$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
"$exe" part2.nml > part2.log 2>&1 || { tail part2.log; fail "restart failed"; }
grep -q "restarted from" part2.log || fail "the log does not report the restart"
cmp out/straight_tracks.txt out/split_tracks.txt || fail "the split run's tracks file differs"
echo "PASS: tracks file checked against the final frame; the split run's equals the straight run's"
