#!/usr/bin/env bash
# The frame series of a run whose particles leave the grid, split by a
# restart after some have left, equals the straight run's: names, times,
# steps and each frame's particle count, the XDMF's counts checked against
# the frame files (restart_frames.py).
# Usage: restart_frames_particles.sh EXE PYTHON DECK N M WORKDIR
#   (split at step N, straight and continued runs to step M; frames every 50 steps)
set -u
exe=$1 py=$2 deck=$3 n=$4 m=$5 dir=$6
here=$(cd "$(dirname "$0")" && pwd)
. "$here/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
frames() { sed -i -e "s|^\(&output .*\)/ *\$|\1, frame_steps = 50 /|" "$1.nml"; }
run() { "$exe" "$1.nml" > "$1.log" 2>&1 || { tail -5 "$1.log"; fail "$1 failed"; }; }
series() { "$py" "$here/restart_frames.py" out "$1" > "$1.series" || { cat "$1.series"; fail "series of $1"; }; }
derive straight "$deck" "max_steps = $m" straight; frames straight
derive part1 "$deck" "max_steps = $n, dump_steps = $n" split; frames part1
derive part2 "$deck" "max_steps = $m, restart_from = '$(printf 'out/split_restart_%08d.h5' "$n")'" split; frames part2
run straight; run part1; run part2
grep -q "left the grid" part1.log || fail "no particle left before the dump at step $n"
series straight; series split
diff straight.series split.series || fail "the split series differs from the straight one"
[ "$(awk '{print $NF}' straight.series | sort -u | wc -l)" -gt 1 ] || fail "the particle count never changes"
echo "ok: split at step $n: $(wc -l < split.series) frames, the same names, times, steps and particle counts"
echo "PASS restart_frames_particles"
