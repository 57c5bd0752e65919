#!/usr/bin/env bash
# The particles in a restart file: what the file holds is what a continued
# run has (a dump whose particle velocity and stress were edited with h5py,
# checksums valid, continues with exactly the edited values), and a file
# with impossible particle data is refused before step 0 (exit status 2,
# a message naming the dataset and the value).
# Usage: restart_particles.sh EXE PYTHON DECK N WORKDIR [FILE...]
set -u
exe=$1 py=$2 deck=$3 n=$4 dir=$5
shift 5
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"
for extra in "$@"; do cp "$extra" "$dir"/ || fail "cannot copy $extra"; done
cd "$dir" || exit 1
dump=$(printf 'out/p_restart_%08d.h5' "$n")
derive part1 "$deck" "max_steps = $n, dump_steps = $n" p
"$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
[ -f "$dump" ] || fail "no dump $dump"

# copy the dump to NAME.h5 and run python statements on it (h5py file f)
edit_file() {
  "$py" - "$dump" "$1.h5" "$2" <<'PY' || fail "$1: could not edit the file"
import shutil, sys
import h5py
import numpy as np
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    exec(sys.argv[3])
PY
}

# 1. round trip: edited particle fields come back exactly in the next frame
edit_file moved 'f["state/particle_velocity"][0] = [1.25, -2.5, 0.1]; f["state/particle_stress"][1] = [1, 2, 3, 4, 5, 6]'
derive moved "$deck" "max_steps = $((n + 1)), restart_from = 'moved.h5'" moved
"$exe" moved.nml > moved.log 2>&1 || { tail -5 moved.log; fail "restart from the edited file failed"; }
"$py" - "$(final_frame moved)" <<'PY' || exit 1
import sys, h5py, numpy as np
f = h5py.File(sys.argv[1])
v = f["particles/velocity"][0]
s = f["particles/stress"][1]            # Tensor6 order xx, xy, xz, yy, yz, zz
want_v = np.array([1.25, -2.5, 0.1])
want_s = np.array([1, 6, 5, 2, 4, 3], dtype=float)
print("particle 1 velocity", v, "expected", want_v)
print("particle 2 stress (xx xy xz yy yz zz)", s, "expected", want_s)
if v.tobytes() != want_v.tobytes() or s.tobytes() != want_s.tobytes():
    sys.exit("FAIL: the continued run does not hold the restart file's particle fields")
PY
echo "ok: the restart file's particle fields continue bit for bit"

# 2. refusals
refuse() {
  local name=$1 regex=$2 code=$3 out rc
  edit_file "$name" "$code"
  derive "$name" "$deck" "max_steps = $((2*n)), restart_from = '$name.h5'" "$name"
  out=$("$exe" "$name.nml" 2>&1); rc=$?
  [ "$rc" -eq 2 ] || { printf '%s\n' "$out" | tail -5; fail "$name: exit status $rc, expected 2"; }
  printf '%s\n' "$out" | grep -E -q -- "$regex" || { printf '%s\n' "$out" | tail -5; fail "$name: no line matches /$regex/"; }
  printf '%s\n' "$out" | grep -E -q '^step ' && fail "$name: a step was taken"
  echo "ok: $name refused: $(printf '%s\n' "$out" | grep -E -- "$regex" | head -1)"
}
refuse cell_beyond_grid "is damaged: state/particle_cell = 99999 at particle 3 \(the grid has cells 1..1000\)" \
  'f["state/particle_cell"][2] = 99999'
refuse material_beyond "state/particle_material = 9 at particle 1 \(this deck has solids 1..2\)" \
  'f["state/particle_material"][0] = 9'
refuse id_repeated "state/particle_id = 1 at particle 2 \(the id is repeated\)" \
  'ids = f["state/particle_id"][()]; ids[ids == 1] = ids[1]; ids[1] = 1; ids[0] = 1; f["state/particle_id"][:] = ids'
refuse mass_negative "state/particle_mass = -1\.0+E\+00 at entry 4 \(particle 4\) \(must be > 0\)" \
  'f["state/particle_mass"][3] = -1.0'
refuse count_changed "particle_x" \
  'x = f["state/particle_x"][()]; del f["state/particle_x"]; f.create_dataset("state/particle_x", data=x[:-1], fletcher32=True)'
echo "PASS: particle restart fields round-trip and damaged ones are refused"
