#!/usr/bin/env bash
# The frame series (names, times, steps) of a run split by a restart equals
# the straight run's, with frame_steps and with frame_dt, when the split falls
# on a frame; and when it does not, the first segment's final frame is kept
# (listed, not overwritten) and the series is the straight run's plus that
# one frame.
# Usage: restart_frames.sh EXE PYTHON DECK WORKDIR   (DECK: t_end = 0.2 in &run)
set -u
exe=$1 py=$2 deck=$3 dir=$4
here=$(cd "$(dirname "$0")" && pwd)
. "$here/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
series() { "$py" "$here/restart_frames.py" out "$1" > "$1.series" || { cat "$1.series"; fail "series of $1"; }; }
# frames OUTPUT_VARS: appends variables to the &output group of the last derived deck
frames() { sed -i -e "s|^\(&output .*\)/ *\$|\1, $2 /|" "$1.nml"; }
run() { "$exe" "$1.nml" > "$1.log" 2>&1 || { tail -5 "$1.log"; fail "$1 failed"; }; }

# 1. frame_steps = 10, split at step 30 (a frame step)
derive s_straight "$deck" "max_steps = 60" s_straight; frames s_straight "frame_steps = 10"
derive s_part1 "$deck" "max_steps = 30, dump_steps = 30" s_split; frames s_part1 "frame_steps = 10"
derive s_part2 "$deck" "max_steps = 60, restart_from = 'out/s_split_restart_00000030.h5'" s_split
frames s_part2 "frame_steps = 10"
run s_straight; run s_part1; run s_part2
series s_straight; series s_split
diff s_straight.series s_split.series || fail "frame_steps: the split series differs from the straight one"
echo "ok: frame_steps = 10, split at step 30: $(wc -l < s_split.series) frames, the same names, times and steps"

# 2. frame_dt = 0.025, the first segment ends at t = 0.05 (a frame time), dumped there
derive t_straight "$deck" "max_steps = 100000" t_straight; frames t_straight "frame_dt = 0.025"
sed -i -e 's/t_end = 0.2/t_end = 0.1/' t_straight.nml
derive t_part1 "$deck" "dump_dt = 0.05" t_split; frames t_part1 "frame_dt = 0.025"
sed -i -e 's/t_end = 0.2/t_end = 0.05/' t_part1.nml
run t_straight; run t_part1
dump=$(ls out/t_split_restart_*.h5 | tail -1)
[ -n "$dump" ] || fail "frame_dt: no dump"
derive t_part2 "$deck" "max_steps = 100000, dump_dt = 0.05, restart_from = '$dump'" t_split
frames t_part2 "frame_dt = 0.025"
sed -i -e 's/t_end = 0.2/t_end = 0.1/' t_part2.nml
run t_part2
series t_straight; series t_split
diff t_straight.series t_split.series || fail "frame_dt: the split series differs from the straight one"
echo "ok: frame_dt = 0.025, split at t = 0.05 ($dump): $(wc -l < t_split.series) frames, the same names, times and steps"
# the continued run's dumps: the next one on the schedule (t = 0.1) alone, not
# the one it was continued from again at its first step
dumps=$(grep '^restart .* at step ' t_part2.log | sed 's/.*, t = //; s/ (.*//')
[ "$dumps" = "1.0000000E-01" ] || fail "dump_dt = 0.05 continued from t = 0.05: dumps at '$dumps', not at 1.0000000E-01 alone"
echo "ok: the continued run dumps at t = 0.1 alone"

# 3. frame_steps = 10, split at step 25 (no frame due): segment 1's final frame
#    is kept and listed; otherwise the straight run's series
derive u_straight "$deck" "max_steps = 60" u_straight; frames u_straight "frame_steps = 10"
derive u_part1 "$deck" "max_steps = 25, dump_steps = 25" u_split; frames u_part1 "frame_steps = 10"
derive u_part2 "$deck" "max_steps = 60, restart_from = 'out/u_split_restart_00000025.h5'" u_split
frames u_part2 "frame_steps = 10"
run u_straight; run u_part1
end1=$(final_frame u_split)
sum1=$(md5sum < "$end1")
run u_part2
[ "$(md5sum < "$end1")" = "$sum1" ] || fail "the continued run overwrote $end1"
series u_straight; series u_split
grep -q "  25$" u_split.series || fail "segment 1's final frame (step 25) is not in the series"
grep -v "  25$" u_split.series | awk '{ print $2, $3 }' > u_split.rest
awk '{ print $2, $3 }' u_straight.series > u_straight.rest
diff u_straight.rest u_split.rest || fail "split at step 25: apart from step 25, the series differs"
echo "ok: split at step 25 (no frame due): $end1 kept and listed, the other frames at the straight run's times and steps"
echo "PASS restart_frames"
