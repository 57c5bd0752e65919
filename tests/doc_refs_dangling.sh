#!/usr/bin/env bash
# tools/check_doc_refs.py must catch dangling references: a copy of the
# repository (its top-level entries linked, README.md copied) whose README
# cites a file outside the repository, a section PARTICLES.md does not have
# and a source file that does not exist must fail with those three lines.
# Usage: doc_refs_dangling.sh PYTHON3 SOURCE_DIR WORKDIR
set -u
py=$1 src=$2 dir=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir" || exit 1
for e in "$src"/* "$src"/.ci; do
  [ "$(basename "$e")" = README.md ] || [ "$(basename "$e")" = build ] || ln -s "$e" "$dir/"
done
cp "$src/README.md" "$dir/"
# (the names are assembled so that this script itself cites nothing)
d=DESIGN s=§ f=no_such_driver
printf 'See `../shared/%s.md`, PARTICLES.md %s9.9 and `src/%s.f90`.\n' "$d" "$s" "$f" >> "$dir/README.md"
out=$("$py" "$src/tools/check_doc_refs.py" "$dir") && fail "the check passed a README with three dangling references"
echo "$out"
echo "$out" | grep -q "README.md:[0-9]*: ../shared/$d.md is not a file of the repository" || fail "outside file not caught"
echo "$out" | grep -q "PARTICLES.md has no section 9.9" || fail "missing section not caught"
echo "$out" | grep -q "\`src/$f.f90\` does not exist" || fail "missing source file not caught"
echo "$out" | grep -q "^3 dangling reference" || fail "expected exactly 3 dangling references"
echo "PASS: the three dangling references are caught"
