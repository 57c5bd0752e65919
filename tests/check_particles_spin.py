#!/usr/bin/env python3
"""Ladder rung 6 of issue 14: a projectile rotating in a light fluid keeps
its angular momentum.

    check_particles_spin.py OUTDIR TOL

Over every frame in OUTDIR (sorted), the particles' angular momentum about
the z axis, L = sum_p m_p (x v_y - y v_x), against the first frame's:
passes if max |L/L0 - 1| <= TOL and the last frame is not the first.
Run with /usr/bin/python3.
"""
import glob
import os
import sys

import h5py
import numpy as np


def main():
    frames = sorted(glob.glob(os.path.join(sys.argv[1], "*.h5")))
    tol = float(sys.argv[2])
    worst, l0 = 0.0, None
    for path in frames:
        with h5py.File(path, "r") as f:
            x, v, m = f["particles/x"][()], f["particles/velocity"][()], f["particles/mass"][()]
            t = float(f["time"][()])
        lz = float(np.sum(m * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0])))
        l0 = lz if l0 is None else l0
        worst = max(worst, abs(lz / l0 - 1.0))
        print(f"t = {t:.3f}: L = {lz:.10g}, L/L0 - 1 = {lz / l0 - 1.0:+.3e}")
    ok = len(frames) > 1 and worst <= tol
    print(f"max |L/L0 - 1| = {worst:.3e} over {len(frames)} frames (tolerance {tol:.1e})")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
