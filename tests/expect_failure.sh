#!/usr/bin/env bash
# Runs EXE on DECK, expecting a failure before step 0: a non-zero exit (the
# given STATUS, if one is given), a message matching REGEX, and no time step
# taken.
# Usage: expect_failure.sh EXE DECK REGEX [STATUS]
set -u
exe=$1; deck=$2; regex=$3; want=${4:-}
out=$("$exe" "$deck" 2>&1); rc=$?
printf '%s\n' "$out"
if [ "$rc" -eq 0 ]; then echo "FAIL: exit status 0, expected non-zero"; exit 1; fi
if [ -n "$want" ] && [ "$rc" -ne "$want" ]; then echo "FAIL: exit status $rc, expected $want"; exit 1; fi
if ! printf '%s\n' "$out" | grep -E -q -- "$regex"; then echo "FAIL: no line matches /$regex/"; exit 1; fi
if printf '%s\n' "$out" | grep -E -q '^step '; then echo "FAIL: the run took a step before stopping"; exit 1; fi
echo "PASS: exit status $rc and message /$regex/"
