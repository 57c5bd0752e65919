#!/usr/bin/env bash
# A deck that takes its materials from the library (&material library = ...)
# gives the same frames bit for bit as the deck with the entry's values
# written out (the entry in the deck's own unit system: read exactly).
# Usage: library_explicit.sh EXE PYTHON COMPARE DECK STEPS WORKDIR 'SED' ...
# (each SED turns one library line of DECK into its explicit values)
set -u
exe=$1 py=$2 cmp=$3 deck=$4 n=$5 dir=$6
shift 6
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
grep -q "library = " "$deck" || fail "$deck takes nothing from the library"
args=()
for e in "$@"; do args+=(-e "$e"); done
for v in library explicit; do
  sed -e "s|^&output.*|\&output dir = 'out_$v', name = 'run', frame_dt = 0 /|" -e "s|^\(&run .*\)/ *\$|\1, max_steps = $n /|" \
      "$deck" > $v.nml
done
sed -i "${args[@]}" explicit.nml
! grep -q "library = " explicit.nml || fail "explicit.nml still names the library: $(grep 'library = ' explicit.nml)"
"$exe" library.nml > library.log 2>&1 || fail "the library deck failed (see $dir/library.log)"
"$exe" explicit.nml > explicit.log 2>&1 || fail "the explicit deck failed (see $dir/explicit.log)"
last=$(ls out_library/*_0*.h5 | tail -1)
out=$("$py" "$cmp" --exact "$last" "out_explicit/$(basename "$last")") || { echo "$out" | tail; fail "the frames differ"; }
echo "$out" | tail -1
echo "PASS: the library deck and the explicit deck give the same frames after $n steps"
