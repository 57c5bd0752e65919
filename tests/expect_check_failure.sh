#!/usr/bin/env bash
# `lsalepm --check DECK` must refuse the deck: exit status 2 and a message
# matching REGEX (the same refusal the run gives before step 0).
# Usage: expect_check_failure.sh EXE DECK REGEX
set -u
exe=$1; deck=$2; regex=$3
out=$("$exe" --check "$deck" 2>&1); rc=$?
printf '%s\n' "$out" | grep -E -- 'ERROR|valid'
if [ "$rc" -ne 2 ]; then echo "FAIL: --check exit status $rc, expected 2"; exit 1; fi
if ! printf '%s\n' "$out" | grep -E -q -- "$regex"; then echo "FAIL: no line matches /$regex/"; exit 1; fi
echo "PASS: --check exit status 2 and message /$regex/"
