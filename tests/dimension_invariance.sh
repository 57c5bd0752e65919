#!/usr/bin/env bash
# Dimensional consistency: the deck with lengths scaled by 2^L, times by 2^T
# and masses by 2^M (tools/scale_deck.py) gives every frame of the original
# run scaled by the power of two of each field's dimension, bit for bit
# (tools/check_scaling.py). A power of two changes no significand, so any
# difference is a dimensional constant in the code (an absolute epsilon, a
# default or an algorithm whose rounding depends on the magnitude of a
# dimensional value).
# Every HDF5 frame is compared (the gauge text files are not).
# Usage: dimension_invariance.sh EXE PYTHON TOOLS DECK N L T M WORKDIR
#   TOOLS: the directory of scale_deck.py and check_scaling.py;
#   N: max_steps of both runs, or 'all' for the deck's whole run.
set -u
exe=$1 py=$2 tools=$3 deck=$4 n=$5 l=$6 t=$7 m=$8 dir=$9
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
[ "$n" = all ] && n=100000000
"$py" "$tools/scale_deck.py" "$deck" scaled_deck.nml --L "$l" --T "$t" --M "$m" || fail "scale_deck.py refused $deck"
derive orig "$deck" "max_steps = $n" orig
derive scaled scaled_deck.nml "max_steps = $n" scaled
OMP_NUM_THREADS=1 "$exe" orig.nml > orig.log 2>&1 || fail "original run failed (see $dir/orig.log)"
OMP_NUM_THREADS=1 "$exe" scaled.nml > scaled.log 2>&1 || fail "scaled run failed (see $dir/scaled.log)"
grep -h '^done:' orig.log scaled.log
frames=$(cd out && ls orig_[0-9][0-9][0-9][0-9][0-9].h5)
nscaled=$(cd out && ls scaled_[0-9][0-9][0-9][0-9][0-9].h5 | wc -l)
[ "$(echo "$frames" | wc -l)" -eq "$nscaled" ] || fail "the runs wrote different numbers of frames"
status=0
for f in $frames; do
  "$py" "$tools/check_scaling.py" "out/$f" "out/scaled_${f#orig_}" --L "$l" --T "$t" --M "$m" || status=1
done
exit $status
