#!/usr/bin/env python3
"""Uniformity check: a pure translation (a uniform flow carrying bodies of
any density at one pressure) must stay one.

    check_uniform.py FRAME P0 UX UY UZ TOL

Checks the largest |p - P0|/P0 over the cells (and over every material's
own pressure where it is present) and the largest |u - U|/|U| over the
nodes of FRAME against TOL. Run with /usr/bin/python3 (Debian numpy and
h5py).
"""
import sys

import h5py
import numpy as np


def main():
    frame = sys.argv[1]
    p0 = float(sys.argv[2])
    u0 = np.array([float(v) for v in sys.argv[3:6]])
    tol = float(sys.argv[6])
    with h5py.File(frame, "r") as f:
        dp = float(np.max(np.abs(f["pressure"][()] - p0))) / p0
        for key in f.keys():
            if key.startswith("pressure_"):
                mask = f["vf_" + key[len("pressure_"):]][()] > 0.0
                if mask.any():
                    dp = max(dp, float(np.max(np.abs(f[key][()][mask] - p0))) / p0)
        u = f["velocity"][()].reshape(-1, 3)
        t = float(f["time"][()])
    du = float(np.max(np.linalg.norm(u - u0, axis=1))) / float(np.linalg.norm(u0))
    print(f"t = {t:.4g}: max |p - p0|/p0 {dp:.3e}, max |u - u0|/|u0| {du:.3e}; tolerance {tol:.1e}")
    ok = dp <= tol and du <= tol
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
