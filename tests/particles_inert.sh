#!/usr/bin/env bash
# Particles are not coupled to the gas yet (issue 14, foundation): a deck
# with &solid and &particles groups must leave every gas field bit for bit
# as the same deck without them, and the deck without them must write no
# particle dataset.
# Usage: particles_inert.sh EXE PYTHON COMPARE DECK WORKDIR
set -u
exe=$1 py=$2 cmp=$3 deck=$4 dir=$5
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
# drop the particle groups (each may continue on indented lines)
awk '/^&(solid|particles)/ {skip = 1; next} skip && /^[ \t]/ {next} {skip = 0; print}' "$deck" |
  sed -e "s|^&output.*|\&output dir = 'out', name = 'gas' /|" > gas.nml
sed -e "s|^&output.*|\&output dir = 'out', name = 'both' /|" -e "s|file = '|file = '$(dirname "$deck")/|" \
  "$deck" > both.nml
grep -q '^&particles' gas.nml && fail "could not drop the particle groups"
"$exe" gas.nml > gas.log 2>&1 || fail "run without particles failed"
"$exe" both.nml > both.log 2>&1 || { cat both.log; fail "run with particles failed"; }
last() { ls out/"$1"_[0-9][0-9][0-9][0-9][0-9].h5 | sort | tail -1; }
"$py" - "$(last gas)" "$(last both)" <<'PY' || exit 1
import sys, h5py
gas, both = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
if "particles" in gas:
    sys.exit("FAIL: the run without particles wrote particle datasets")
if "particles" not in both:
    sys.exit("FAIL: the run with particles wrote none")
print("particles in the frame:", both["particles/x"].shape[0])
PY
# the gas fields, bit for bit (compare_frames --exact on the shared fields)
"$py" - "$(last gas)" "$(last both)" <<'PY'
import sys, h5py, numpy as np
a, b = h5py.File(sys.argv[1]), h5py.File(sys.argv[2])
names = [n for n in a if isinstance(a[n], h5py.Dataset) and n != "deck"] + ["totals/" + k for k in a["totals"]]
bad = [n for n in names if a[n].shape != b[n].shape or a[n][()].tobytes() != b[n][()].tobytes()]
for n in names:
    print(f"{n:28s} {'identical' if n not in bad else 'DIFFERENT'}")
sys.exit("FAIL: gas fields differ" if bad else 0)
PY
rc=$?
[ $rc -eq 0 ] && echo "PASS: the particles leave the gas bit for bit unchanged"
exit $rc
