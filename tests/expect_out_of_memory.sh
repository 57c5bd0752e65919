#!/usr/bin/env bash
# Runs EXE on DECK under an address-space limit of LIMIT KiB (ulimit -v),
# expecting the failure of expect_failure.sh with REGEX and exit status 1
# (a runtime failure), and not gfortran's "Attempt to allocate an allocated
# object", which its ALLOCATE reports for any failed allocation.
# Usage: expect_out_of_memory.sh EXE DECK LIMIT REGEX
set -u
exe=$1; deck=$2; limit=$3; regex=$4
out=$(ulimit -v "$limit" && bash "$(dirname "$0")/expect_failure.sh" "$exe" "$deck" "$regex" 1 2>&1); rc=$?
printf '%s\n' "$out"
if printf '%s\n' "$out" | grep -q 'Attempt to allocate an allocated object'; then
  echo "FAIL: the message is gfortran's, not out of memory"; exit 1
fi
exit $rc
