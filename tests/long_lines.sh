#!/usr/bin/env bash
# Deck lines of any length (issue 40): the 64 gauges of the documented
# maximum on one line of 3000 characters, a &run line padded past 3000
# characters and a comment that runs past the cut (with a '/' in it) must be
# read as written; a restart of that deck re-reads the stored text the same
# way and continues; a quoted string longer than a deck line is refused
# naming its line.
# Usage: long_lines.sh EXE PYTHON DECK WORKDIR   (DECK: sod2_mid100.nml)
set -u
exe=$1 py=$2 deck=$3 dir=$4
. "$(dirname "$0")/restart_lib.sh"
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
"$py" - "$deck" <<'PY' || fail "could not write the decks"
import sys
gauges = ", ".join(f"{0.005 + 0.0155 * k:.10f}, 0.0050000000, 0.0050000000" for k in range(64))
lines = []
for line in open(sys.argv[1]).read().splitlines():
    if line.startswith("&output"):
        line = ("&output dir = 'out', name = 'long', gauge = " + gauges + ", gauge_dt = 0.01 /"
                "   ! 64 gauges on one line " + "x" * 300 + " / not the end of a group")
    if line.startswith("&run"):
        line = "&run title = 'long lines', dump_steps = 20, " + " " * 3000 + "t_end = 0.05 /"
    lines.append(line)
open("long.nml", "w").write("\n".join(lines) + "\n")
print("longest line:", max(len(l) for l in lines), "characters")
text = open("long.nml").read().replace("title = 'long lines'", "title = '" + "y" * 1500 + "'")
open("long_string.nml", "w").write(text)
PY
"$exe" long.nml > long.out 2>&1 || { tail -5 long.out; fail "the deck of long lines did not run"; }
grep -q "^done: t = 5.0000000E-02" long.out || fail "t_end of the padded &run line was not read"
n=$(grep -c "^# gauge [0-9]* at" out/long_gauges.txt)
[ "$n" -eq 64 ] || fail "$n gauges, not 64"
grep -q "^# gauge 64 at   9.8150000000000004E-001" out/long_gauges.txt || fail "gauge 64 is not at x = 0.9815"
echo "ok: 64 gauges on one line, the padded &run line and the long comment read as written"
sed -e "s|dump_steps = 20,|restart_from = 'out/long_restart_00000020.h5',|" long.nml > cont.nml
"$exe" cont.nml > cont.out 2>&1 || { tail -5 cont.out; fail "the restart of the deck of long lines failed"; }
grep -q "^done: t = 5.0000000E-02" cont.out || fail "the restart did not run to t_end"
echo "ok: its restart re-reads the stored deck and continues"
"$exe" long_string.nml > string.out 2>&1; rc=$?
[ "$rc" -eq 2 ] || fail "a 1500-character string: exit status $rc, not 2"
grep -q "^ERROR: long_string.nml:2: a quoted string or a word longer than 1022 characters" string.out || \
  { cat string.out; fail "the long string is not refused naming line 2"; }
echo "ok: a quoted string longer than a deck line is refused naming its line"
echo "PASS long_lines"
