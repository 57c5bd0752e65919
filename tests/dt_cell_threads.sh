#!/usr/bin/env bash
# Every progress line names the cell (i,j,k) and material that set the step,
# and 1 and 2 threads name the same cells (ties go to the lowest cell index).
# Usage: dt_cell_threads.sh EXE DECK STEPS WORKDIR
set -u
exe=$1 deck=$2 steps=$3 dir=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
sed -e "s|^\(&run .*\)/ *\$|\1, max_steps = $steps, progress_steps = 1 /|" \
    -e "s|^&output.*|\&output dir = 'out' /|" "$deck" > run.nml
OMP_NUM_THREADS=1 "$exe" run.nml > one.log 2>&1 || fail "1-thread run failed"
OMP_NUM_THREADS=2 "$exe" run.nml > two.log 2>&1 || fail "2-thread run failed"
sed -n 's/^step .*dt by //p' one.log > one.txt
sed -n 's/^step .*dt by //p' two.log > two.txt
[ "$(wc -l < one.txt)" -ge "$steps" ] || fail "fewer than $steps progress lines name what set the step"
grep -q '^cell ([0-9]*,[0-9]*,[0-9]*) ' one.txt || fail "no step was set by a cell"
diff one.txt two.txt > /dev/null || { diff one.txt two.txt | head; fail "1 and 2 threads name different cells"; }
echo "$(grep -c '^cell' one.txt) of $(wc -l < one.txt) steps set by a cell, the same with 1 and 2 threads; e.g."
head -2 one.txt
echo "PASS"
