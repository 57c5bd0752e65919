#!/usr/bin/env bash
# Output control (&output fields, particle_fields, precision = 'single',
# compress): a deck that chooses fields, float32 and deflate (DECK) runs
# 1. straight to step 2N (dumps every N steps),
# 2. split: to step N with a dump, then restarted from it to step 2N,
# 3. straight to step 2N with precision = 'double' and compress = 0;
# then the frames hold just the chosen fields, float32, compressed, with an
# XDMF listing them (check_output_control.py content), the split run's last
# frame and its dump at step 2N equal the straight run's bit for bit (a
# restart of a compressed single-precision run continues exactly: dumps stay
# double, checksummed, uncompressed), and every frame of run 1 is float32()
# of run 3's, bit for bit. A restart that changes the frames' precision or
# fields is refused; one that changes compress runs.
# Usage: output_control.sh EXE PYTHON COMPARE DECK N WORKDIR
set -u
exe=$1 py=$2 cmp=$3 deck=$4 n=$5 dir=$6
here=$(cd "$(dirname "$0")" && pwd)
. "$here/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
m=$((2*n))
# make NEW NAME RUN_VARS: the deck with &run variables added, its outputs in
# out/ under NAME (the deck's other &output choices kept)
make_deck() {
  sed -e "s|^\(&run .*\)/ *\$|\1, $3 /|" -e "s|dir = '[^']*'|dir = 'out', name = '$2'|" "$deck" > "$1.nml"
  grep -q "name = '$2'" "$1.nml" || fail "could not derive $1.nml from $deck"
}
run() { "$exe" "$1.nml" > "$1.log" 2>&1 || { tail -5 "$1.log"; fail "$1 failed (see $dir/$1.log)"; }; }
make_deck straight straight "max_steps = $m, dump_steps = $n"
make_deck part1 split "max_steps = $n, dump_steps = $n"
make_deck part2 split "max_steps = $m, dump_steps = $n, restart_from = '$(printf 'out/split_restart_%08d.h5' "$n")'"
make_deck double double "max_steps = $m"
sed -i -e "s|precision = 'single'|precision = 'double'|" -e "s|compress = [0-9]|compress = 0|" double.nml
grep -q "precision = 'double'" double.nml && grep -q "compress = 0" double.nml || fail "could not derive double.nml"
run straight; run part1; run part2; run double
grep -q "restarted from out/split_restart" part2.log || fail "the log does not report the restart"
"$py" "$here/check_output_control.py" content out straight || fail "frame content"
"$py" "$cmp" "$(final_frame straight)" "$(final_frame split)" --exact || fail "the split run's last frame differs"
"$py" "$here/check_output_control.py" dumps "$(printf 'out/straight_restart_%08d.h5' "$m")" \
  "$(printf 'out/split_restart_%08d.h5' "$m")" || fail "the dumps at step $m differ"
# a restart that changes the frames' precision or fields is refused (the
# XDMF series lists the earlier frames with the new layout); compress may change
refused() { # name regex
  local out rc
  out=$("$exe" "$1.nml" 2>&1); rc=$?
  [ "$rc" -eq 2 ] || { printf '%s\n' "$out" | tail -5; fail "$1: exit status $rc, expected 2"; }
  printf '%s\n' "$out" | grep -E -q -- "$2" || { printf '%s\n' "$out" | tail -5; fail "$1: no line matches /$2/"; }
  echo "ok: $1 refused: $(printf '%s\n' "$out" | grep -E -- "$2" | head -1)"
}
dump=$(printf 'out/split_restart_%08d.h5' "$n")
make_deck to_double split "max_steps = $m, restart_from = '$dump'"
sed -i -e "s|precision = 'single'|precision = 'double'|" to_double.nml
refused to_double "&output precision changed from 'single' to 'double'"
make_deck more_fields split "max_steps = $m, restart_from = '$dump'"
sed -i -e "s|'damage',|'damage', 'porosity',|" more_fields.nml
refused more_fields "&output particle_fields changed from 'velocity', 'stress', 'id', 'failed', 'temperature', 'damage' to .*'porosity'"
make_deck recompress recompress "max_steps = $((n + 1)), restart_from = '$dump'"
sed -i -e "s|compress = [0-9]|compress = 1|" recompress.nml
run recompress
echo "ok: a restart with another compress level runs"
mkdir -p dbl && mv out/double_* dbl/ && for f in dbl/double_*.h5; do mv "$f" "dbl/straight_${f#dbl/double_}"; done
"$py" "$here/check_output_control.py" versus out dbl straight || fail "single against double"
echo "bytes: single + compress $(cat out/straight_[0-9]*.h5 | wc -c), double uncompressed $(cat dbl/straight_[0-9]*.h5 | wc -c)"
echo "PASS output_control"
