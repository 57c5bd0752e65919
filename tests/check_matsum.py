#!/usr/bin/env python3
"""The material and body sums file (&output history_dt) against the energy
history of the same run.

    check_matsum.py OUT/NAME REL_TOL

OUT/NAME_matsum.txt has, at every row time of OUT/NAME_history.txt, one row
per grid material and one per particle body: time kind index name mass
momentum_x momentum_y momentum_z kinetic internal volume. Checked at every time:
  - the same materials and bodies;
  - the internal energies of the materials and bodies add up to the
    history's internal energy (which holds the particles' own);
  - without bodies, the materials' kinetic energies add up to the
    history's kinetic energy (through the cells' corner masses, exact);
  - the total mass of the materials and each body's mass stay at their
    first values (a closed box: the decks this checks lose no mass);
  - the materials' volumes add up to the grid's volume (a closed box whose
    walls stay: its first row's total).
All within REL_TOL of the initial total energy (or of the mass).
"""
import sys
from collections import defaultdict

prefix, tol = sys.argv[1], float(sys.argv[2])
hist = [list(map(float, l.split())) for l in open(prefix + "_history.txt") if not l.startswith("#")]
rows = defaultdict(list)
lines = open(prefix + "_matsum.txt").read().splitlines()
header = [l for l in lines if l.startswith("#")]
if not header or header[-1].split()[1:] != ["time", "kind", "index", "name", "mass", "momentum_x", "momentum_y",
                                             "momentum_z", "kinetic", "internal", "volume"]:
    sys.exit("FAIL: the matsum file has no header naming its columns")
for l in lines:
    if l.startswith("#"):
        continue
    f = l.split()
    rows[f[0]].append((f[1], int(f[2]), f[3], *map(float, f[4:])))
times = sorted(rows, key=float)
if len(times) != len(hist):
    sys.exit(f"FAIL: {len(times)} row times in the matsum file, {len(hist)} in the history")
e0 = abs(hist[0][1] + hist[0][2])
bad = 0
first = None


def check(ok, what):
    global bad
    if not ok:
        print("FAIL", what)
        bad += 1


for t, h in zip(times, hist):
    r = rows[t]
    check(abs(float(t) - h[0]) <= 1e-15 * max(abs(h[0]), 1.0), f"t = {t}: history row at {h[0]}")
    key = [(x[0], x[1], x[2]) for x in r]
    if first is None:
        first = {x[0:3]: x for x in r}
        mass0 = sum(x[3] for x in r if x[0] == "material")
        volume0 = sum(x[9] for x in r if x[0] == "material")
    check(key == list(first), f"t = {t}: materials and bodies {key} differ from the first row's")
    mats = [x for x in r if x[0] == "material"]
    bodies = [x for x in r if x[0] == "body"]
    internal = sum(x[8] for x in r)
    check(abs(internal - h[2]) <= tol * e0, f"t = {t}: internal {internal:.16e} against the history's {h[2]:.16e}")
    if not bodies:
        kinetic = sum(x[7] for x in mats)
        check(abs(kinetic - h[1]) <= tol * e0, f"t = {t}: kinetic {kinetic:.16e} against the history's {h[1]:.16e}")
    volume = sum(x[9] for x in mats)
    check(abs(volume - volume0) <= tol * volume0, f"t = {t}: the materials' volume {volume:.16e} against {volume0:.16e}")
    mass = sum(x[3] for x in mats)
    check(abs(mass - mass0) <= tol * mass0, f"t = {t}: the materials' mass {mass:.16e} against {mass0:.16e}")
    for b in bodies:
        m0 = first[b[0:3]][3]
        check(abs(b[3] - m0) <= tol * m0, f"t = {t}: body {b[1]} mass {b[3]:.16e} against {m0:.16e}")
print(f"{len(times)} times, {len(first)} rows each "
      f"({sum(1 for k in first if k[0] == 'material')} materials, {sum(1 for k in first if k[0] == 'body')} bodies); "
      f"tolerance {tol:.1e}")
if bad:
    sys.exit(f"FAIL: {bad} checks")
print("PASS")
