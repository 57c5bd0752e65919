#!/usr/bin/env bash
# Coupled particles through Euler steps remapped in parts of the way
# (&rezone swept_parts): the deck (its &rezone line with swept_parts > 1,
# its first track point a particle) run as it is and with swept_parts = 1
# (the same steps in two remaps, the second by intersection: swept_hybrid).
# The first must remap every Euler step in parts (the log's "in N parts of
# the way") and close its energy budget with the particles to BUDGET (the
# final conservation report's residual over |E0|; each part is a
# conservative remap and the particles' share of the nodal momentum is
# taken once, before the first part); the second must take some steps in
# two remaps. The tracked particle's displacement at t_end must agree
# between the two within REL of the two-remap run's: the two ways differ
# only in how each remap reconstructs the fluid, not in what the particles
# carry through the step.
# Usage: particles_parts.sh EXE DECK WORKDIR BUDGET REL
set -u
exe=$1 deck=$2 dir=$3 budget=$4 rel=$5
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir"; mkdir -p "$dir"; cd "$dir" || exit 1
grep -q '^&rezone.*swept_parts = [2-9]' "$deck" || fail "the deck's &rezone line sets no swept_parts > 1"
sed -e "s|^&output dir = '[^']*'|\&output dir = 'parts'|" "$deck" > parts.nml
sed -e "s|^&output dir = '[^']*'|\&output dir = 'two'|" -e 's/swept_parts = [0-9]*/swept_parts = 1/' "$deck" > two.nml
for run in parts two; do
  "$exe" $run.nml > $run.log 2>&1 || { tail -20 $run.log; fail "the $run run failed"; }
done
e=$(grep -c '^euler [0-9]* at' parts.log)
p=$(grep -c '^euler [0-9]* at.* in [0-9]* parts of the way' parts.log)
h=$(grep -c '^euler [0-9]* at.* in two remaps' two.log)
echo "parts: $p of $e Euler steps in parts of the way; swept_parts = 1: $h steps in two remaps"
[ "$e" -gt 0 ] && [ "$p" -eq "$e" ] || fail "not every Euler step in parts"
[ "$h" -gt 0 ] || fail "no step in two remaps with swept_parts = 1"
awk -v b="$budget" '/^conservation \(final\)/ {f = 1} f && /energy budget over/ {r = $NF}
  END {if (r == "") {print "FAIL: no final energy budget"; exit 1}
       a = r < 0 ? -r : r; printf "parts: energy budget residual %s (bound %s)\n", r, b; if (!(a <= b)) exit 1}' parts.log ||
  fail "the energy budget does not close"
# (columns: time, id_1, x_1: the tracked particle's x, first and last rows)
awk -v rel="$rel" 'FNR == 1 {f++} /^#/ {next} {if (!(f in x0)) x0[f] = $3; x1[f] = $3}
  END {d1 = x1[1] - x0[1]; d2 = x1[2] - x0[2]; r = (d1 - d2)/d2; if (r < 0) r = -r
       printf "tracked x displacement: parts %.6e, two remaps %.6e, relative difference %.2e (bound %s)\n", d1, d2, r, rel
       if (!(d2 != 0 && r <= rel)) exit 1}' parts/parts_tracks.txt two/two_tracks.txt ||
  fail "the particles' displacement differs between the two ways"
echo "PASS"
