#!/usr/bin/env bash
# 1 and 2 OpenMP threads give bit-for-bit the same random field, samples and
# void fractions: the white noise is drawn serially in one order, FFTW runs
# outside parallel regions, and the threaded loops write each value from the
# same operands (strength_random_field's notes).
# Usage: random_field_threads.sh EXE WORKDIR
set -u
exe=$1 dir=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
OMP_NUM_THREADS=1 "$exe" one.txt || fail "1-thread run failed"
OMP_NUM_THREADS=2 "$exe" two.txt || fail "2-thread run failed"
cmp -s one.txt two.txt || { diff one.txt two.txt | head; fail "1 and 2 threads differ"; }
echo "$(wc -l < one.txt) values (hex), identical with 1 and 2 threads; $(head -1 one.txt)"
echo "PASS"
