#!/usr/bin/env bash
# Regenerates regression/<case>/reference.h5 from the given build (use the
# debug build, the one `make test` compares with). Commit the new references
# with a message that says why the new numbers are right.
# Usage: tools/regression_update.sh EXE [CASE ...]   (default: every case)
set -euo pipefail
exe=$(realpath "$1"); shift
root=$(cd "$(dirname "$0")/.." && pwd)
decks=()
if [ $# -eq 0 ]; then
  decks=("$root"/regression/*/deck.nml)
else
  for c in "$@"; do decks+=("$root/regression/$c/deck.nml"); done
fi
for deck in "${decks[@]}"; do
  case_dir=$(dirname "$deck"); name=$(basename "$case_dir")
  work=$(mktemp -d)
  (cd "$work" && "$exe" "$deck" > run.log 2>&1) || { echo "regression-update: $name failed; see $work/run.log"; exit 1; }
  cp "$work/out/result_00001.h5" "$case_dir/reference.h5"
  rm -rf "$work"
  echo "regression-update: $name -> regression/$name/reference.h5"
done
