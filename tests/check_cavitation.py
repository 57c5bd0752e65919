#!/usr/bin/env python3
"""The water column of tests/decks/cavitation_column.nml against the
acoustic answers of the cut-off model (the deck's header), from the gauge
file: gauge 1 in the cell at the left wall, gauge 2 at mid-column.

    check_cavitation.py cutoff OUT/NAME   (p_min = 2.34 kPa: cavity and reload)
    check_cavitation.py tension OUT/NAME  (no cut-off: the wall holds tension)

cutoff: behind the tension front (gauge 2 at t = 3 us) the velocity is
u1 = u0 - (p0 - p_min)/(rho0 c0) to 0.5 % and the pressure p_min to 1e-12
relative; the wall's cell never goes below p_min and stays there until the
cavity closes, which it does within 5 % of 2L/c0 (the cavity is a few cells
wide and its closure is seen when the wall's cell is compressed again; the
compression is a shock slightly faster than c0); the reload, the median
wall pressure over the microsecond after the closure's first 0.1 us (the
first cell overshoots), within 2 % of p_min + rho0 (c0 + s1 u1) u1.
tension: the wall cell's median pressure from 0.5 to 3 us within 1 % of
p0 - rho0 c0 u0 (the linear tension branch).
"""
import sys

import numpy as np

mode, prefix = sys.argv[1], sys.argv[2]
rho0, c0, s1, u0, p0, p_min, length = 1.0, 1.48, 1.75, 0.01, 1.0e-4, 2.34e-6, 10.0
lines = open(prefix + "_gauges.txt").read().splitlines()
cols = [l for l in lines if l.startswith("#")][-1].split()[1:]
a = np.array([l.split() for l in lines if not l.startswith("#")], float)
t = a[:, cols.index("time")]
p1, p2 = a[:, cols.index("pressure_1")], a[:, cols.index("pressure_2")]
u2 = a[:, cols.index("velocity_x_2")]
bad = 0


def check(ok, what):
    global bad
    bad += not ok
    print(("ok   " if ok else "FAIL ") + what)


if mode == "tension":
    want = p0 - rho0 * c0 * u0
    held = np.median(p1[(t >= 0.5) & (t <= 3.0)])
    check(abs(held - want) <= 0.01 * abs(want), f"wall cell's pressure {held:.4e} (linear branch {want:.4e})")
else:
    u1 = u0 - (p0 - p_min) / (rho0 * c0)
    k = np.searchsorted(t, 3.0)
    check(abs(u2[k] - u1) <= 5e-3 * u1, f"velocity behind the tension front {u2[k]:.6f} (u1 {u1:.6f})")
    check(abs(p2[k] - p_min) <= 1e-12 * p_min, f"pressure there {p2[k]:.6e} (p_min {p_min:.6e})")
    check(p1.min() >= p_min * (1 - 1e-12), f"wall cell's least pressure {p1.min():.4e} (p_min {p_min:.4e})")
    t_close = 2 * length / c0
    p_reload = p_min + rho0 * (c0 + s1 * u1) * u1
    late = np.nonzero((t > 1.0) & (p1 > p0 + 0.5 * (p_reload - p0)))[0]
    if late.size == 0:
        check(False, "the cavity never closed")
    else:
        tc = t[late[0]]
        check(abs(tc - t_close) <= 0.05 * t_close,
              f"cavity closed at {tc:.3f} us (2L/c0 {t_close:.3f}, {100 * (tc / t_close - 1):+.2f} %)")
        held = np.median(p1[(t >= tc + 0.1) & (t <= tc + 1.0)])
        check(abs(held - p_reload) <= 0.02 * p_reload,
              f"reload {held:.4e} (p_min + rho0 Us u1 {p_reload:.4e}, {100 * (held / p_reload - 1):+.2f} %)")
sys.exit(1 if bad else 0)
