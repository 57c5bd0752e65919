#!/usr/bin/env bash
# A damaged restart's particles, read by the blocks (each reads only the
# particles its cells host, and the ids are checked over the ranks: no rank
# holds the whole run's): a dump of 2 ranks rewritten through h5py (valid
# checksums: only the restart's own checks can find the damage) with one
# particle's id that of another far from it in the file (repeated), one
# particle's body changed, and one host cell outside the grid. One process
# and 3 and 4 ranks refuse each with exit status 2 and the same message,
# printed once, naming the particle by its place in the file.
# Usage: mpi_restart_damaged_particles.sh MPIEXEC EXE PYTHON DECK WORKDIR
set -u
mpiexec=$1 exe=$2 py=$3 deck=$4 dir=$5
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
export OMP_NUM_THREADS=1
derive part "$deck" "max_steps = 10, dump_steps = 10" part
timeout 300 "$mpiexec" "${root[@]}" --oversubscribe -np 2 "$exe" part.nml > part.log 2>&1 || fail "the 2-rank run to step 10 failed"
"$py" - out/part_restart_00000010.h5 <<'PY' > want.txt || fail "could not damage the dump"
import shutil, sys
import h5py, numpy as np
src = sys.argv[1]
for bad in ('repeated', 'body', 'cell'):
    shutil.copy(src, bad + '.h5')
with h5py.File('repeated.h5', 'r+') as h:
    ids = h['state/particle_id'][...]
    n = len(ids)
    ids[n - 2] = ids[1]          # the later of the two in the file is named
    h['state/particle_id'][...] = ids
    print('repeated|state/particle_id = %d at particle %d (the id is repeated)' % (ids[1], n - 1))
with h5py.File('body.h5', 'r+') as h:
    b = h['state/particle_body'][...]
    k = len(b) // 3
    was = b[k]
    b[k] = was + 1
    h['state/particle_body'][...] = b
    i = h['state/particle_id'][k]
    print('body|state/particle_body = %d at particle %d (the deck seeds particle %d in body %d)' % (was + 1, k + 1, i, was))
with h5py.File('cell.h5', 'r+') as h:
    c = h['state/particle_cell'][...]
    k = (2 * len(c)) // 3
    ncell = int(np.prod(h['state/material'].shape))
    c[k] = ncell + 7
    h['state/particle_cell'][...] = c
    print('cell|state/particle_cell = %d at particle %d (the grid has cells 1..%d)' % (ncell + 7, k + 1, ncell))
PY
while IFS='|' read -r bad want; do
  derive $bad "$deck" "max_steps = 20, restart_from = '$bad.h5'" $bad
  for np in 1 3 4; do
    timeout 300 "$mpiexec" "${root[@]}" --oversubscribe -np $np "$exe" $bad.nml < /dev/null > $bad$np.log 2>&1; rc=$?
    [ $rc -eq 124 ] && fail "$np ranks, $bad: hung (killed after 300 s)"
    [ $rc -eq 2 ] || { tail -5 $bad$np.log; fail "$np rank(s), $bad: exit status $rc, not 2"; }
    [ "$(grep -c -F "$want" $bad$np.log)" -eq 1 ] || { grep -E "ERROR|FATAL" $bad$np.log; fail "$np rank(s): not one line saying '$want'"; }
    echo "ok: $np rank(s) refuse the dump: $want"
  done
done < want.txt
[ "$(ls cell4.log 2> /dev/null)" ] || fail "not every damage was tried"
echo "PASS mpi_restart_damaged_particles"
