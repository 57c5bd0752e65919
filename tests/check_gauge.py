#!/usr/bin/env python3
"""Gauge history check: the Sod shock reaches the gauge at the exact time.

    check_gauge.py GAUGES.txt X_GAUGE TOL

Sod (gamma 1.4, (1,0,1) | (0.125,0,0.1) at x0 = 0.5): the right shock moves at
S = 1.75216 (exact Riemann solution), so it reaches x at (x - 0.5)/S. The
gauge's arrival time is when its density first passes halfway between the
pre-shock 0.125 and post-shock 0.26557 values; it must be within TOL of the
exact time. Gauge rows are: time, then cell, density, pressure, energy,
sound speed, velocity x/y/z for each gauge.
"""
import sys

import numpy as np

path, x, tol = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
rows = np.loadtxt(path, comments="#")
t, rho = rows[:, 0], rows[:, 2]
if not (abs(rho[0] - 0.125) < 1e-12):
    print(f"FAIL: initial gauge density {rho[0]} is not the right state 0.125")
    sys.exit(1)
half = 0.5 * (0.125 + 0.26557371)
hit = np.nonzero(rho > half)[0]
if hit.size == 0:
    print("FAIL: the shock never reached the gauge")
    sys.exit(1)
i = hit[0]
# linear interpolation between the two rows around the crossing
ta = t[i - 1] + (half - rho[i - 1]) * (t[i] - t[i - 1]) / (rho[i] - rho[i - 1])
exact = (x - 0.5) / 1.7521557
print(f"shock arrival at x = {x}: {ta:.5f}, exact {exact:.5f}, difference {ta - exact:+.2e}, tolerance {tol:.1e}")
if abs(ta - exact) > tol:
    print("FAIL: arrival time outside tolerance")
    sys.exit(1)
print("PASS check_gauge")
