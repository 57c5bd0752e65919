#!/usr/bin/env bash
# Restarts that must be refused before step 0 with a message naming the
# problem (changed grid, material, initial velocity field or fixed boxes, truncated,
# foreign or missing file), and one that must be accepted (new end time and
# output name).
# Usage: restart_refusals.sh EXE DECK WORKDIR PYTHON
set -u
exe=$1 deck=$2 dir=$3 py=$4
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
derive base "$deck" "max_steps = 10, dump_steps = 10" base
"$exe" base.nml > base.log 2>&1 || fail "base run failed"
dump=out/base_restart_00000010.h5
[ -f "$dump" ] || fail "no dump"
head -c 3000 "$dump" > truncated.h5

expect() { # name regex deck
  local out rc
  out=$("$exe" "$3" 2>&1); rc=$?
  [ "$rc" -eq 2 ] || { printf '%s\n' "$out"; fail "$1: exit status $rc, expected 2"; }
  printf '%s\n' "$out" | grep -E -q -- "$2" || { printf '%s\n' "$out"; fail "$1: no line matches /$2/"; }
  printf '%s\n' "$out" | grep -E -q '^step ' && fail "$1: a step was taken"
  echo "ok: $1 refused: $(printf '%s\n' "$out" | grep -E -- "$2" | head -1)"
}
derive grid "$deck" "max_steps = 20, restart_from = '$dump'" base
sed -i -e 's/ni = 100/ni = 50/' grid.nml
expect "changed grid" "&grid ni changed from 100 to 50" grid.nml
derive graded "$deck" "max_steps = 20, restart_from = '$dump'" base
sed -i -e 's|xmax = 1, 0.01, 0.01 /|xmax = 1, 0.01, 0.01, spacing_x = 0, 0.005, 1, 0.01 /|' graded.nml
expect "graded grid" "&grid spacing_x changed" graded.nml
derive gamma "$deck" "max_steps = 20, restart_from = '$dump'" base
sed -i -e 's/gamma = 1.4/gamma = 1.67/' gamma.nml
expect "changed gamma" "&material 'gas' gamma changed" gamma.nml
derive field "$deck" "max_steps = 20, restart_from = '$dump'" base
sed -i -e "s/^&region shape = 'all',/\&region shape = 'all', velocity_field = 'rotation', angular_velocity = 1,/" field.nml
expect "changed velocity field" "&region\\(1\\) velocity_field changed" field.nml
expect "changed angular velocity" "&region\\(1\\) angular_velocity changed" field.nml
derive fixed "$deck" "max_steps = 20, restart_from = '$dump'" base
sed -i -e "s|^&boundary xlo = 'wall', xhi = 'wall' /|\&boundary xlo = 'wall', xhi = 'wall', fixed_lo = 0.5, 0, 0, fixed_hi = 0.5, 1, 1 /|" fixed.nml
expect "fixed box added" "&boundary fixed boxes changed from 0 to 1" fixed.nml
derive trunc "$deck" "max_steps = 20, restart_from = 'truncated.h5'" base
expect "truncated file" "restart_from: cannot read restart file" trunc.nml
derive foreign "$deck" "max_steps = 20, restart_from = 'out/base_00000.h5'" base
expect "a frame, not a restart" "is not a restart file" foreign.nml
"$py" - "$dump" future.h5 <<'PY'
import shutil, sys, h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    f["restart_version"][()] = 99
PY
derive future "$deck" "max_steps = 20, restart_from = 'future.h5'" base
expect "another format version" "has restart format version 99; this program reads version 5" future.nml
"$py" - "$dump" old.h5 <<'PY'
import shutil, sys, h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    f["restart_version"][()] = 1
PY
derive old "$deck" "max_steps = 20, restart_from = 'old.h5'" base
expect "the format before mixed-cell sizes were stored" "has restart format version 1; this program reads version 5" old.nml
"$py" - "$dump" reshaped.h5 <<'PY'
import shutil, sys, h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    rho = f["state/density"][()]
    del f["state/density"]
    f["state/density"] = rho[:50]
PY
derive reshaped "$deck" "max_steps = 20, restart_from = 'reshaped.h5'" base
expect "a field of the wrong size" "state/density has shape \\(50\\), this run expects \\(100\\)" reshaped.nml
derive missing "$deck" "max_steps = 20, restart_from = 'nowhere.h5'" base
expect "missing file" "restart_from: cannot read restart file" missing.nml

derive fine "$deck" "max_steps = 20, restart_from = '$dump'" renamed
sed -i -e 's/t_end = 0.2/t_end = 0.15/' fine.nml
"$exe" fine.nml > fine.log 2>&1 || { cat fine.log; fail "an allowed change was refused"; }
grep -q "done: .* after 20 steps" fine.log || fail "the accepted restart did not run to step 20"
echo "ok: new end time and output name accepted"
echo "PASS restart_refusals"
