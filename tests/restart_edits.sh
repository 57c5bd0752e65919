#!/usr/bin/env bash
# Restart files edited with h5py (so their checksums are valid) to hold
# impossible values: each must be refused before step 0 with exit status 2
# and a message naming the dataset and the value; the slot count of 1e9 under
# a 2 GB address-space limit, so that allocating it first would fail
# differently. Then the unedited file is accepted.
# Usage: restart_edits.sh EXE PYTHON DECK N WORKDIR   (DECK with mixed cells)
set -u
exe=$1 py=$2 deck=$3 n=$4 dir=$5
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
dump=$(printf 'out/e_restart_%08d.h5' "$n")
derive part1 "$deck" "max_steps = $n, dump_steps = $n" e
"$exe" part1.nml > part1.log 2>&1 || fail "first part failed"
[ -f "$dump" ] || fail "no dump $dump"

refused=0
# edit NAME REGEX PYTHON_STATEMENTS: copy the dump to NAME.h5, run the
# statements on it (h5py file f, numpy np), continue from it, expect a refusal
edit() {
  local name=$1 regex=$2 code=$3 out rc
  "$py" - "$dump" "$name.h5" "$code" <<'PY' || fail "$name: could not edit the file"
import shutil, sys
import h5py
import numpy as np
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    exec(sys.argv[3])
PY
  derive "$name" "$deck" "max_steps = $((2*n)), restart_from = '$name.h5'" "$name"
  out=$(ulimit -v 2000000; "$exe" "$name.nml" 2>&1); rc=$?
  [ "$rc" -eq 2 ] || { printf '%s\n' "$out" | tail -5; fail "$name: exit status $rc, expected 2"; }
  printf '%s\n' "$out" | grep -q "^ERROR: cannot restart" || { printf '%s\n' "$out"; fail "$name: no 'cannot restart'"; }
  printf '%s\n' "$out" | grep -E -q -- "$regex" || { printf '%s\n' "$out"; fail "$name: no line matches /$regex/"; }
  printf '%s\n' "$out" | grep -E -q '^step ' && fail "$name: a step was taken"
  echo "ok: $name refused: $(printf '%s\n' "$out" | grep -E -- "$regex" | head -1)"
  refused=$((refused + 1))
}
edit material_beyond_nmat "state/material = 7 in cell 3 \(this deck has materials 1..2" \
  'f["state/material"][2] = 7'
edit nan_time "scalars/time is NaN" 'f["scalars/time"][...] = np.nan'
edit negative_step "scalars/step = -5 \(must be >= 0\)" 'f["scalars/step"][...] = -5'
edit nframe_1e5 "scalars/nframe = 100000, but output/frames lists [0-9]+ frames" 'f["scalars/nframe"][...] = 100000'
edit mixed_nslot_1e9 "scalars/mixed_nslot = 1000000000 needs \(1000000000\)" \
  'f["scalars/mixed_nslot"][...] = 1000000000'
edit nan_density "state/density has NaN at entry 11 \(cell 11\)" 'f["state/density"][10] = np.nan'
# and more of the same kinds
edit mixed_n_1e9 "scalars/mixed_n = 1000000000" 'f["scalars/mixed_n"][...] = 1000000000'
edit mixed_n_shape "state/mixed_cell has shape .* but scalars/mixed_n = 2 needs \(2\)" \
  'f["scalars/mixed_n"][...] = 2; f["scalars/mixed_nslot"][...] = 4'
edit negative_dt "scalars/dt = -1" 'f["scalars/dt"][...] = -1.0'
edit inf_t_next_frame "scalars/t_next_frame is \+Infinity" 'f["scalars/t_next_frame"][...] = np.inf'
edit negative_volume "state/volume = -.* at entry 5 \(cell 5\) \(must be > 0\)" 'f["state/volume"][4] *= -1'
edit zero_mass "state/mass = 0.* at entry 1 \(cell 1\) \(must be > 0\)" 'f["state/mass"][0] = 0.0'
edit nan_velocity "state/velocity has NaN at entry 7 \(node 3\)" 'v = f["state/velocity"][()]; v[2, 0] = np.nan; f["state/velocity"][...] = v'
edit inf_x "state/x has -Infinity" 'v = f["state/x"][()]; v[0, 0] = -np.inf; f["state/x"][...] = v'
edit nan_mixed_density "state/mixed_density has NaN" 'f["state/mixed_density"][0] = np.nan'
edit negative_mixed_mass "state/mixed_mass = -" 'f["state/mixed_mass"][1] *= -1'
edit mixed_material_0 "state/mixed_material = 0 in slot 1" 'f["state/mixed_material"][0] = 0'
edit zero_rng "scalars/rng_state is zero" 'f["scalars/rng_state"][...] = 0.0'
edit nan_frame_time "output/times has NaN at entry 1" 'f["output/times"][0] = np.nan'
edit frame_times_long "output/times has 1000001 entries, output/frames names [0-9]+ frames" \
  't = f["output/times"][()]; del f["output/times"]; f["output/times"] = np.zeros(1000001)'
edit negative_n_euler "scalars/n_euler = -1" 'f["scalars/n_euler"][...] = -1'
echo "$refused edited files refused"

derive fine "$deck" "max_steps = $((2*n)), restart_from = '$dump'" fine
"$exe" fine.nml > fine.log 2>&1 || { tail -5 fine.log; fail "the unedited file was refused"; }
grep -q "done: .* after $((2*n)) steps" fine.log || fail "the unedited restart did not run to step $((2*n))"
echo "ok: the unedited file continues to step $((2*n))"
echo "PASS restart_edits"
