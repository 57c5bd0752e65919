#!/usr/bin/env python3
"""Domain check: the nodes of a frame span the box LO..HI (a grid whose
open faces are held at their standard places must not drift with the flow).

    check_extent.py FRAME XLO YLO ZLO XHI YHI ZHI TOL

Compares the smallest and largest node coordinate in each direction with
LO and HI; TOL is absolute. Run with /usr/bin/python3 (Debian numpy and h5py).
"""
import sys

import h5py
import numpy as np


def main():
    frame = sys.argv[1]
    lo = np.array([float(v) for v in sys.argv[2:5]])
    hi = np.array([float(v) for v in sys.argv[5:8]])
    tol = float(sys.argv[8])
    with h5py.File(frame, "r") as f:
        x = f["x"][()].reshape(-1, 3)
        t = float(f["time"][()])
    xlo, xhi = x.min(axis=0), x.max(axis=0)
    err = max(float(np.max(np.abs(xlo - lo))), float(np.max(np.abs(xhi - hi))))
    print(f"t = {t:.4g}: nodes span {xlo} .. {xhi}; largest difference {err:.3e}, tolerance {tol:.1e}")
    ok = err <= tol
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
