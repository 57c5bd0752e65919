#!/usr/bin/env python3
"""The asymmetry of a TNT sphere lit at its centre against one lit at a pole.

    check_detonation_sphere.py CENTRE_OUT/NAME POLE_OUT/NAME RADIUS DETONATOR_OFFSET

From each run's log the lighting times (`lit from T0 to T1`) and the CJ
velocity D; from its gauges at z = +8 and z = -8 the arrival of the air
shock (the first row where the pressure exceeds twice the ambient 1e-4).
  - Lit at the centre: the last cell centres light at about R/D (within
    one cell diagonal over D: the mixed cells at the surface hold some
    explosive), and both gauges see the shock in the same row (the scene is
    symmetric under z -> -z).
  - Lit at the pole (the detonator DETONATOR_OFFSET inside the lower pole):
    the last cells light at about (2R - offset)/D, the same tolerance; the
    lower gauge sees the shock first, the upper one later by at least a
    quarter of the lighting delay 2R/D (the far side's products start 1.3 us
    later and catch up only partly through their detonation-direction
    velocity; measured 0.7 us of 1.3 at 20^3).
  - The pole-lit run's line of 7 gauges along x (&output gauge_line from
    (-9, 0, 0) to (9, 0, 0)): gauges 3..9 of its blast answers sit at
    x = -9, -6, ..., 9, and mirror pairs (x and -x: the scene is symmetric
    under x -> -x) have the same arrival and peak to 1e-6 relative (the two
    sides differ only by the order of round-off: 1.4e-9 measured at the shock
    foot, where the overpressure is 1e-5 of the charge's CJ pressure).
"""
import re
import sys

import numpy as np

RADIUS, OFFSET = float(sys.argv[3]), float(sys.argv[4])
CELL_DIAG = np.sqrt(3.0)   # the deck's 1 mm cells


def run(prefix):
    log = open(prefix + ".log").read()
    d = float(re.search(r"CJ velocity\s+([^,\s]+),", log).group(1))
    t0, t1 = map(float, re.search(r"lit from t =\s+(\S+) to\s+(\S+)", log).groups())
    lines = open(prefix + "_gauges.txt").read().splitlines()
    head = [l for l in lines if l.startswith("#")][-1].split()[1:]
    rows = np.array([list(map(float, l.split())) for l in lines if not l.startswith("#")])
    arrive = []
    for g in (1, 2):
        p = rows[:, head.index(f"pressure_{g}")]
        k = np.argmax(p > 2.0e-4)
        if not p[k] > 2.0e-4:
            sys.exit(f"FAIL: {prefix}: no shock at gauge {g}")
        arrive.append(rows[k, 0])
    return d, t1, arrive


bad = 0


def check(ok, what):
    global bad
    bad += not ok
    print(("ok   " if ok else "FAIL ") + what)


d, t1, (up, low) = run(sys.argv[1])
check(abs(t1 - RADIUS / d) <= CELL_DIAG / d,
      f"centre-lit: last lighting {t1:.4f} against R/D = {RADIUS / d:.4f} (tolerance {CELL_DIAG / d:.4f})")
check(up == low, f"centre-lit: the shock reaches z = +8 at {up:.4f} and z = -8 at {low:.4f}: the same row")
d, t1, (up, low) = run(sys.argv[2])
far = (2 * RADIUS - OFFSET) / d
check(abs(t1 - far) <= CELL_DIAG / d,
      f"pole-lit: last lighting {t1:.4f} against (2R - offset)/D = {far:.4f} (tolerance {CELL_DIAG / d:.4f})")
check(up - low >= 0.25 * 2 * RADIUS / d,
      f"pole-lit: the shock reaches z = -8 at {low:.4f}, z = +8 at {up:.4f}: later by {up - low:.4f} "
      f">= a quarter of 2R/D = {2 * RADIUS / d:.4f}")
rows = {int(l.split()[0]): [float(v) for v in l.split()[1:]] for l in open(sys.argv[2] + "_blast.txt")
        if not l.startswith("#")}
line = [rows.get(g) for g in range(3, 10)]
check(all(r is not None for r in line) and all(abs(r[0] - (-9 + 3 * k)) < 1e-12 and r[1] == 0 and r[2] == 0
                                               for k, r in enumerate(line)),
      "gauge line: gauges 3..9 at x = -9, -6, ..., 9 on the x axis")
if all(r is not None for r in line):
    for k in range(3):
        a, b = line[k], line[6 - k]
        same = all(abs(a[i] - b[i]) <= 1e-6 * max(abs(a[i]), 1e-300) for i in (4, 5))
        check(same, f"mirror gauges x = {a[0]:g} and {b[0]:g}: arrival {a[4]:.9f} / {b[4]:.9f}, "
                    f"peak {a[5]:.6e} / {b[5]:.6e}")
sys.exit(1 if bad else 0)
