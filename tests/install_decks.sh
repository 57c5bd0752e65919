#!/usr/bin/env bash
# `cmake --install` gives a tree in which every shipped deck passes
# `lsalepm --check` from another directory (the files a deck reads, such as
# steel_shell_points.txt, are installed next to it), with the docs and tools.
# Usage: install_decks.sh CMAKE BUILD_DIR WORKDIR
set -u
cmake=$1 build=$2 dir=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir/elsewhere" || exit 1
"$cmake" --install "$build" --prefix "$dir/prefix" > "$dir/install.log" 2>&1 || { tail "$dir/install.log"; fail "install failed"; }
share="$dir/prefix/share/lsalepm"
for f in README.md input/README.md docs/ARCHITECTURE.md docs/PARTICLES.md tools/check_doc_refs.py; do
  [ -f "$share/$f" ] || fail "$f not installed"
done
cd "$dir/elsewhere" || exit 1
n=0
for deck in "$share"/input/*.nml; do
  "$dir/prefix/bin/lsalepm" --check "$deck" > check.log 2>&1 || { tail -3 check.log; fail "installed $(basename "$deck") fails --check"; }
  n=$((n + 1))
done
[ "$n" -ge 10 ] || fail "only $n decks installed"
echo "PASS: $n installed decks pass --check"
