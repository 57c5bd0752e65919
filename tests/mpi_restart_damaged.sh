#!/usr/bin/env bash
# A damaged restart read block by block (a decomposed run without Euler
# steps or particles reads only its block's nodes and cells): two mixed
# cells of a dump have their numbers in state/material swapped (the file
# rewritten through h5py, so its checksums are valid: only the restart's own
# consistency check can find it). The single process refuses it; on 2 and 4
# ranks only the blocks holding those cells see it, yet every rank must end
# with exit status 2 and the same refusal, without hanging. The same for a
# NaN in a mixed slot and mixed cells' starts out of order, which a block
# reads only when they are its own.
# Usage: mpi_restart_damaged.sh MPIEXEC EXE PYTHON DECK WORKDIR
set -u
mpiexec=$1 exe=$2 py=$3 deck=$4 dir=$5
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
export OMP_NUM_THREADS=1
derive part1 "$deck" "max_steps = 10, dump_steps = 10" part1
derive bad "$deck" "max_steps = 20, restart_from = 'bad.h5'" bad
"$exe" part1.nml > part1.log 2>&1 || fail "the run to step 10 failed"
"$py" - out/part1_restart_00000010.h5 bad.h5 <<'PY' || fail "could not damage the dump"
import shutil, sys
import h5py, numpy as np
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], 'r+') as h:
    m = h['state/material'][...]
    a, b = np.where(m == -1)[0][0], np.where(m == -2)[0][0]
    m[a], m[b] = -2, -1
    h['state/material'][...] = m
PY
want="bad.h5 is damaged: its mixed cells do not match its cell materials"
"$exe" bad.nml > one.log 2>&1; rc=$?
[ $rc -eq 2 ] || fail "one process: exit status $rc, not 2"
grep -q "$want" one.log || fail "one process: no refusal naming the damage"
for np in 2 4; do
  timeout 120 "$mpiexec" "${root[@]}" --oversubscribe -np $np "$exe" bad.nml > ranks$np.log 2>&1; rc=$?
  [ $rc -eq 124 ] && fail "$np ranks: hung (killed after 120 s)"
  [ $rc -eq 2 ] || { tail -5 ranks$np.log; fail "$np ranks: exit status $rc, not 2"; }
  [ "$(grep -c "$want" ranks$np.log)" -eq 1 ] || { cat ranks$np.log; fail "$np ranks: the refusal is not printed once"; }
  echo "ok: $np ranks refuse the damaged dump with exit 2, printed once"
done
# a node coordinate of 1e300 (the deck's magnitude rule; issue 40: it
# crashed a global sum), dumped by 2 ranks, read on 1 and 3
derive part2 "$deck" "max_steps = 10, dump_steps = 10" part2
derive huge "$deck" "max_steps = 20, restart_from = 'huge.h5'" huge
timeout 120 "$mpiexec" "${root[@]}" --oversubscribe -np 2 "$exe" part2.nml > part2.log 2>&1 || fail "the 2-rank run to step 10 failed"
"$py" - out/part2_restart_00000010.h5 huge.h5 <<'PY' || fail "could not damage the dump"
import shutil, sys
import h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], 'r+') as h:
    x = h['state/x'][...]
    x[x.shape[0] // 2, 1] = 1e300      # node nnode/2 + 1, its y
    h['state/x'][...] = x
    node = x.shape[0] // 2 + 1
print("node", node)
PY
node=$("$py" -c "import h5py; print(h5py.File('huge.h5')['state/x'].shape[0] // 2 + 1)")
want="huge.h5 is damaged: state/x = 1.0000000E+300 at entry $((3*node - 1)) (node $node)"
for np in 1 3; do
  timeout 120 "$mpiexec" "${root[@]}" --oversubscribe -np $np "$exe" huge.nml > huge$np.log 2>&1; rc=$?
  [ $rc -eq 124 ] && fail "$np ranks: hung (killed after 120 s)"
  [ $rc -eq 2 ] || { tail -5 huge$np.log; fail "$np rank(s), node at 1e300: exit status $rc, not 2"; }
  [ "$(grep -c -F "$want" huge$np.log)" -eq 1 ] || { grep -E "ERROR|FATAL" huge$np.log; fail "$np rank(s): not one line saying '$want'"; }
  echo "ok: $np rank(s) refuse the dump with a node at 1e300: $want"
done
# the mixed cells a block reads alone (its own runs of the file's lists):
# a slot's energy NaN is named by its place in the file on every count of
# ranks; the starts of two mixed cells out of order are refused as damage
"$py" - out/part2_restart_00000010.h5 nan.h5 starts.h5 <<'PY' || fail "could not damage the dump"
import shutil, sys
import h5py, numpy as np
shutil.copy(sys.argv[1], sys.argv[2])
shutil.copy(sys.argv[1], sys.argv[3])
with h5py.File(sys.argv[2], 'r+') as h:
    e = h['state/mixed_energy'][...]
    e[len(e) // 2] = np.nan
    h['state/mixed_energy'][...] = e
with h5py.File(sys.argv[3], 'r+') as h:
    s = h['state/mixed_start'][...]
    k = len(s) // 2
    s[k] = s[k + 1]
    h['state/mixed_start'][...] = s
PY
slot=$("$py" -c "import h5py; print(len(h5py.File('nan.h5')['state/mixed_energy']) // 2 + 1)")
for bad in nan starts; do
  derive $bad "$deck" "max_steps = 20, restart_from = '$bad.h5'" $bad
  if [ $bad = nan ]; then
    want="nan.h5 is damaged: state/mixed_energy has NaN at entry $slot (mixed slot $slot)"
  else
    want="starts.h5 is damaged: its mixed cells do not match its cell materials"
  fi
  for np in 1 3 4; do
    timeout 120 "$mpiexec" "${root[@]}" --oversubscribe -np $np "$exe" $bad.nml > $bad$np.log 2>&1; rc=$?
    [ $rc -eq 124 ] && fail "$np ranks: hung (killed after 120 s)"
    [ $rc -eq 2 ] || { tail -5 $bad$np.log; fail "$np rank(s), $bad: exit status $rc, not 2"; }
    [ "$(grep -c -F "$want" $bad$np.log)" -eq 1 ] || { grep -E "ERROR|FATAL" $bad$np.log; fail "$np rank(s): not one line saying '$want'"; }
    echo "ok: $np rank(s) refuse the dump: $want"
  done
done
echo "PASS mpi_restart_damaged"
