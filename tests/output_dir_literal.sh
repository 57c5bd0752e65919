#!/usr/bin/env bash
# The output directory is created without a shell: a name with $(...),
# backticks, quotes or a leading -- is taken literally and nothing runs.
# Usage: output_dir_literal.sh EXE WORKDIR
set -u
exe=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
for dir in 'out/$(touch pwned)' 'out/`touch pwned2`' 'out/"q"/a b' '--help' 'out/x;touch pwned3'; do
  printf "&run t_end = 0.01 /\n&grid ni = 4, nj = 1, nk = 1 /\n&material gamma = 1.4 /\n" > d.nml
  printf "&region density = 1, pressure = 1 /\n&output dir = '%s', name = 'd' /\n" "$dir" >> d.nml
  "$exe" d.nml > log.txt 2>&1 || { cat log.txt; fail "the run with dir = $dir failed"; }
  [ -f "$dir/d_00001.h5" ] || fail "no frame in the literal directory '$dir'"
  echo "ok: '$dir' created literally"
done
ls pwned* 2>/dev/null && fail "a command in a directory name was run"
echo "PASS: no directory name was interpreted"
