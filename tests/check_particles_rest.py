#!/usr/bin/env python3
"""Ladder rung 1 of issue 14: an elastic block prestressed to -p0 I in gas
at rest at pressure p0 must stay at rest.

    check_particles_rest.py FRAME0 FRAME P0 TOL

Compares, in FRAME (after many steps) against FRAME0 (the start): the
largest node speed and particle speed (against TOL times the sound-speed
scale sqrt(p0)), the largest |p - p0|/p0 over the cells, the largest change
of any particle stress component over p0, and the largest particle
displacement (over the grid's extent). Run with /usr/bin/python3.
"""
import sys

import h5py
import numpy as np


def main():
    f0, f1 = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
    p0, tol = float(sys.argv[3]), float(sys.argv[4])
    step = int(f1["step"][()])
    checks = {
        "node speed / sqrt(p0)": np.max(np.linalg.norm(f1["velocity"][()].reshape(-1, 3), axis=1)) / np.sqrt(p0),
        "particle speed / sqrt(p0)": np.max(np.linalg.norm(f1["particles/velocity"][()], axis=1)) / np.sqrt(p0),
        "|p - p0| / p0": np.max(np.abs(f1["pressure"][()] - p0)) / p0,
        "|stress change| / p0": np.max(np.abs(f1["particles/stress"][()] - f0["particles/stress"][()])) / p0,
        "particle displacement / extent": np.max(np.abs(f1["particles/x"][()] - f0["particles/x"][()]))
        / np.ptp(f0["x"][()].reshape(-1, 3)),
    }
    ok = step > 0
    print(f"after {step} steps (t = {float(f1['time'][()]):.4g}), tolerance {tol:.1e}:")
    for label, value in checks.items():
        good = value <= tol
        ok = ok and good
        print(f"  {label:32s} {value:.3e}  {'ok' if good else 'FAIL'}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
