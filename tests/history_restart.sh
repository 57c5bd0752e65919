#!/usr/bin/env bash
# The energy history, material sums and gauge files of a run split by a restart equal the
# straight run's byte for byte, even when the first part ran on past the
# dump it is continued from (its later rows are dropped on restart).
# Usage: history_restart.sh EXE DECK N HISTORY_DT WORKDIR
# (DECK's &output line is replaced; its gauge points are kept.)
set -u
exe=$1 deck=$2 n=$3 hdt=$4 dir=$5
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
gauge=$(sed -n "s/^&output.*\(gauge *=[^/]*\)\/.*/\1/p" "$deck")
# make NEW NAME RUN_VARS: the deck with &output dir 'out', name NAME, the
# history interval and the deck's gauges, and RUN_VARS added to &run
make() {
  sed -e "s|^\(&run .*\)/ *\$|\1 $3 /|" \
      -e "s|^&output.*|\&output dir = 'out', name = '$2', history_dt = $hdt, $gauge /|" "$deck" > "$1.nml"
}
make straight straight ""
make part1 split ", max_steps = $((n + 15)), dump_steps = $n"
make part2 split ", restart_from = 'out/split_restart_$(printf %08d "$n").h5'"
"$exe" straight.nml > straight.log 2>&1 || fail "straight run failed (see $dir/straight.log)"
"$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
"$exe" part2.nml > part2.log 2>&1 || { tail part2.log; fail "restart failed"; }
rows=$(grep -vc '^#' out/straight_history.txt)
grep -q '^# time kinetic internal boundary_work total drift$' out/straight_history.txt \
  || fail "no header row naming the history columns"
[ "$rows" -ge 5 ] || fail "only $rows history rows"
echo "history: $rows rows; gauges: $(grep -vc '^#' out/straight_gauges.txt) rows"
cmp out/straight_history.txt out/split_history.txt || fail "the split run's history differs"
cmp out/straight_gauges.txt out/split_gauges.txt || fail "the split run's gauge file differs"
cmp out/straight_matsum.txt out/split_matsum.txt || fail "the split run's material sums differ"
echo "PASS: split history, material sums and gauge files equal the straight run's"
