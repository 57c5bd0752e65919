#!/usr/bin/env bash
# Runs EXE on DECK, expecting a run-time failure reported, not a crash: exit
# status 1 (a signal gives 128 + its number), a FATAL line, and the state at
# failure written to the frame the log names.
# Usage: failure_reported.sh EXE DECK
set -u
exe=$1; deck=$2
out=$("$exe" "$deck" 2>&1); rc=$?
printf '%s\n' "$out" | grep -E -a 'FATAL|state at failure|signal|Floating|Backtrace' | head -20
if [ "$rc" -ne 1 ]; then echo "FAIL: exit status $rc, expected 1 (a reported failure)"; exit 1; fi
if ! printf '%s\n' "$out" | grep -E -q '^FATAL \[rank 0, step [0-9]+\]'; then echo "FAIL: no FATAL line"; exit 1; fi
frame=$(printf '%s\n' "$out" | sed -n 's/^state at failure written to //p' | tail -1)
if [ -z "$frame" ] || [ ! -s "$frame" ]; then echo "FAIL: no state at failure written"; exit 1; fi
echo "PASS: exit status 1, FATAL reported, state at failure in $frame"
