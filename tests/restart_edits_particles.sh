#!/usr/bin/env bash
# A dump of coupled particles in a closed box, edited with h5py (checksums
# valid) into states the deck and the models cannot produce (issue 40): each
# must be refused before step 0 with exit status 2 and a message naming the
# dataset. A dump's time at or past t_end is refused too (nothing to run);
# a random-generator state whose bits read as a NaN is a valid state (it is
# bits, not a number) and continues; the unedited dump continues, and so
# it does with GIMP supports (&hydro may change: the widths it lacks are set
# from the hosts).
# Usage: restart_edits_particles.sh EXE PYTHON DECK N WORKDIR
#   (DECK: coupled particles with a history variable, no open face)
set -u
exe=$1 py=$2 deck=$3 n=$4 dir=$5
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
dump=$(printf 'out/q_restart_%08d.h5' "$n")
derive part1 "$deck" "max_steps = $n, dump_steps = $n" q
# (the dump with linear supports: it has no widths; the continued runs take
# the default, GIMP, as the last one asks explicitly)
echo "&hydro particle_support = 'linear' /" >> part1.nml
"$exe" part1.nml > part1.log 2>&1 || { tail -5 part1.log; fail "first part failed"; }
[ -f "$dump" ] || fail "no dump $dump"
# run NAME STATUS REGEX PYTHON: copy the dump to NAME.h5, edit it, continue
# from it; expect exit status STATUS and a line matching REGEX
run() {
  local name=$1 want=$2 regex=$3 code=$4 out rc
  "$py" - "$dump" "$name.h5" "$code" <<'PY' || fail "$name: could not edit the file"
import shutil, sys
import h5py
import numpy as np
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    exec(sys.argv[3])
PY
  derive "$name" "$deck" "max_steps = $((n + 2)), restart_from = '$name.h5'" "$name"
  out=$("$exe" "$name.nml" 2>&1); rc=$?
  printf '%s\n' "$out" > "$name.out"
  [ "$rc" -eq "$want" ] || { tail -5 "$name.out"; fail "$name: exit status $rc, expected $want"; }
  grep -E -q -- "$regex" "$name.out" || { tail -5 "$name.out"; fail "$name: no line matches /$regex/"; }
  if [ "$want" -ne 0 ]; then grep -E -q '^step ' "$name.out" && fail "$name: a step was taken"; fi
  echo "ok: $name (exit $rc): $(grep -E -- "$regex" "$name.out" | head -1 | cut -c1-220)"
}
run negative_vf_mass 2 "state/particle_virtual_fluid_mass = -.* at entry 4 \(particle 4\) \(must be >= 0\)" \
  'd = f["state/particle_virtual_fluid_mass"]; d[3] = -abs(d[3]) - 1.0'
run history_1e300 2 "state/particle_history = 1.0+E\+300 at entry .* \(magnitudes of 1e30 or more are refused\)" \
  'd = f["state/particle_history"]; v = d[()]; v[5, 0] = 1e300; d[...] = v'
run stress_1e300 2 "state/particle_stress = 1.0+E\+300 .*magnitudes of 1e30" \
  'd = f["state/particle_stress"]; v = d[()]; v[2, 0] = 1e300; d[...] = v'
run body_minus_1 2 "state/particle_body = -1 at particle 1 \(the deck seeds particle [0-9]+ in body 1\)" \
  'f["state/particle_body"][0] = -1'
run host_moved 2 "state/particle_x of particle 1 is not in its host cell" \
  'f["state/particle_cell"][0] = f["state/particle_cell"][0] + 1'
run one_fewer 2 "holds [0-9]+ particles; the deck seeds [0-9]+ and none can leave \(the deck has no open face\)" '
for k in list(f["state"].keys()):
    if k.startswith("particle_"):
        v = f["state/" + k][()]
        del f["state/" + k]
        f.create_dataset("state/" + k, data=v[:-1], fletcher32=True, chunks=True)
'
run time_1e9 2 "is at t = 1.0+E\+09, at or past &run t_end" 'f["scalars/time"][...] = 1e9'
run x_1e300 2 "state/x = 1.0+E\+300 at entry 4 \(node 2\) \(magnitudes of 1e30" \
  'd = f["state/x"]; v = d[()]; v[1, 0] = 1e300; d[...] = v'
run nan_rng 0 "^done: " 'f["scalars/rng_state"][...] = np.frombuffer(np.uint64(0x7ff8000000000001).tobytes(), dtype=np.float64)[0]'
run unedited 0 "^done: " 'pass'
# the dump (linear supports: no widths) continued with GIMP (a
# restart may change &hydro): the domains from the particles' hosts, logged
derive gimp "$deck" "max_steps = $((n + 2)), restart_from = '$dump'" gimp
echo "&hydro particle_support = 'gimp' /" >> gimp.nml
out=$("$exe" gimp.nml 2>&1); rc=$?
printf '%s\n' "$out" > gimp.out
[ "$rc" -eq 0 ] || { tail -5 gimp.out; fail "gimp: exit status $rc, expected 0"; }
grep -q "has no particle support widths (written with particle_support = 'linear')" gimp.out || \
  { tail -5 gimp.out; fail "gimp: the widths' line is missing"; }
grep -q "^done: " gimp.out || fail "gimp: no done line"
echo "ok: gimp (exit 0): $(grep 'has no particle support widths' gimp.out | cut -c1-160)"
echo "PASS restart_edits_particles"
