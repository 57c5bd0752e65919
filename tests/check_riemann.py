#!/usr/bin/env python3
"""A quasi-1D ideal-gas shock tube run against the exact Riemann solution:
every frame admissible (density > 0, specific internal energy and pressure
>= 0, the cell fields) and the final frame's L1 density error
sum_i |rho_i - <rho>_i| dx_i (cell-averaged exact density) below a bound.

    check_riemann.py FRAME_PREFIX GAMMA RHO_L U_L P_L RHO_R U_R P_R X0 L1_MAX

FRAME_PREFIX_NNNNN.h5 are the frames (the last is the final one).
"""
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import profile_plot as pp  # noqa: E402
from exact.riemann import RiemannSolution  # noqa: E402

prefix = sys.argv[1]
g, rl, ul, pl, rr, ur, pr, x0, l1_max = map(float, sys.argv[2:11])
frames = sorted(glob.glob(prefix + "_[0-9][0-9][0-9][0-9][0-9].h5"))
if not frames:
    sys.exit(f"FAIL: no frames {prefix}_NNNNN.h5")
ok = True
lo = {"density": np.inf, "energy": np.inf, "pressure": np.inf}
for fn in frames:
    fr = pp.read_frame(fn)
    for q in lo:
        lo[q] = min(lo[q], float(np.min(fr[q])))
for q in lo:
    bad = not (lo[q] > 0.0 if q == "density" else lo[q] >= 0.0)
    ok = ok and not bad
    print(f"smallest {q} over {len(frames)} frames {lo[q]:.6e}: {'FAIL' if bad else 'ok'}")
fr = pp.read_frame(frames[-1])
prof = pp.line_profile(fr, "x")
l1 = pp.riemann_l1(prof, RiemannSolution(rl, ul, pl, g, rr, ur, pr, g), fr["time"], x0)
print(f"L1 density error at t = {fr['time']:.6g}: {l1:.6e}, bound {l1_max:g}")
ok = ok and l1 < l1_max
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
