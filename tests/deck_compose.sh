#!/usr/bin/env bash
# A deck written with &parameters, ${...} and &include (issue 38) runs the
# very scene of the flat deck it was written from: final frames bit for bit
# equal; `--check` prints it resolved (the files included, each parameter's
# value, every group's values as used); the log and every frame store that
# resolved text, with no ${...} left.
# Usage: deck_compose.sh EXE PYTHON COMPARE COMPOSE_DIR FLAT_DECK WORKDIR
set -u
exe=$1 py=$2 cmp=$3 src=$4 flat=$5 dir=$6
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cp -r "$src" "$dir/compose" || fail "cannot copy $src"; cd "$dir" || exit 1
# the same 30 steps and outputs for both
sed -e "s|^\(&run .*\)/ *\$|\1, max_steps = 30 /|" -e "s|dir = '[^']*'|dir = 'out', name = 'composed'|" \
    compose/sod_compose.nml > compose/run.nml
sed -e "s|^\(&run .*\)/ *\$|\1, max_steps = 30 /|" -e "s|dir = '[^']*'|dir = 'out', name = 'flat'|" "$flat" > flat.nml
"$exe" --check compose/run.nml > check.txt 2>&1 || { cat check.txt; fail "--check refused the composed deck"; }
for want in '^! included: compose/materials/gas.nml$' '^! parameter h = 1e-2   (compose/run.nml:5)$' \
            '^! parameter gamma_gas = 1.4   (compose/materials/gas.nml:2)$' '^ NI=100 ' '^ GAMMA=  1.3999999999999999 ' \
            '^ DENSITY= 0.12500000000000000 ' 'is valid$'; do
  grep -q -e "$want" check.txt || { cat check.txt; fail "--check prints no line /$want/"; }
done
! grep -q '\${' check.txt || fail "--check prints an unresolved \${...}"
echo "ok: --check prints the resolved deck"
"$exe" compose/run.nml > composed.log 2>&1 || { tail composed.log; fail "the composed deck failed"; }
"$exe" flat.nml > flat.log 2>&1 || { tail flat.log; fail "the flat deck failed"; }
grep -q '^! parameter rho_low = 1.25e-1' out/composed.log || fail "the run log does not hold the resolved deck"
last() { ls out/"$1"_[0-9][0-9][0-9][0-9][0-9].h5 | sort | tail -1; }
"$py" "$cmp" "$(last flat)" "$(last composed)" --exact || fail "the composed deck's final frame differs from the flat deck's"
"$py" - "$(last composed)" << 'PY' || fail "the frame does not store the resolved deck"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    d = f["deck"][()] if "deck" in f else f.attrs["deck"]
text = d.decode() if isinstance(d, bytes) else str(d)
assert "! parameter n = 100" in text and "! included: compose/materials/gas.nml" in text, text[:400]
assert "${" not in text and "&INCLUDE" not in text.upper(), "unresolved text in the frame"
assert " NI=100" in text, text[:400]
print("ok: the frame stores the resolved deck (%d characters)" % len(text))
PY
cmp out/composed_gauges.txt out/flat_gauges.txt || fail "the gauge files differ"
echo "PASS deck_compose: the composed deck runs the flat deck's scene bit for bit"
