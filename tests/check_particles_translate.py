#!/usr/bin/env python3
"""Ladder rung 2 of issue 14: gas and an elastic body (prestressed to -p0 I)
translating together at a uniform velocity U, with Euler steps, must stay a
uniform translation.

    check_particles_translate.py FRAME0 FRAME P0 UX UY UZ E TOL [DRIFT
                                 [XLO YLO ZLO XHI YHI ZHI MARGIN]]

Checks in FRAME against FRAME0 (the start, particles matched by id): the
largest |p - P0|/P0 over the cells, |u - U|/|U| over the nodes and the
particles, the largest stress change over the solid's modulus E (its
strain's round-off), and the particle positions
against x0 + U t (over |U| t). All against TOL. With DRIFT, also the
largest distance of a grid node from its place in FRAME0 against DRIFT
(a localized rezone that lets the grid drift with the flow fails it).
With the grid's box, particles leave through its open faces: those in
FRAME are checked as above, at least one must have left and one remain,
every one that left must have x0 + U t outside the box, and every one
left must be inside it up to MARGIN (the travel over one Euler interval:
particles leave at Euler steps).
Run with /usr/bin/python3.
"""
import sys

import h5py
import numpy as np


def by_id(f, name, ids=None):
    """The particles' values in id order; with ids, only those ids."""
    fid = f["particles/id"][()]
    order = np.argsort(fid)
    if ids is not None:
        order = order[np.isin(fid[order], ids)]
    return f["particles/" + name][()][order]


def main():
    f0, f1 = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
    p0 = float(sys.argv[3])
    u0 = np.array([float(v) for v in sys.argv[4:7]])
    modulus = float(sys.argv[7])
    tol = float(sys.argv[8])
    t = float(f1["time"][()]) - float(f0["time"][()])
    speed = float(np.linalg.norm(u0))
    ids = np.sort(f1["particles/id"][()])
    checks = {
        "|p - p0| / p0 (cells)": np.max(np.abs(f1["pressure"][()] - p0)) / p0,
        "|u - U| / |U| (nodes)": np.max(np.linalg.norm(f1["velocity"][()].reshape(-1, 3) - u0, axis=1)) / speed,
        "|v_p - U| / |U| (particles)": np.max(np.linalg.norm(by_id(f1, "velocity") - u0, axis=1)) / speed,
        "|stress change| / E": np.max(np.abs(by_id(f1, "stress") - by_id(f0, "stress", ids))) / modulus,
        "|x_p - x0 - U t| / (|U| t)": np.max(np.linalg.norm(by_id(f1, "x") - by_id(f0, "x", ids) - u0 * t, axis=1))
        / (speed * t),
    }
    if len(sys.argv) > 9:
        drift = np.max(np.linalg.norm(f1["x"][()].reshape(-1, 3) - f0["x"][()].reshape(-1, 3), axis=1))
        print(f"grid drift {drift:.3e} (bound {float(sys.argv[9]):.3e})  {'ok' if drift <= float(sys.argv[9]) else 'FAIL'}")
        ok0 = drift <= float(sys.argv[9])
    else:
        ok0 = True
    if len(sys.argv) > 16:
        lo, hi = np.array(sys.argv[10:13], float), np.array(sys.argv[13:16], float)
        margin = float(sys.argv[16])
        gone = np.setdiff1d(f0["particles/id"][()], ids)
        xg = by_id(f0, "x", gone) + u0 * t
        outside = np.any((xg < lo) | (xg > hi), axis=1)
        x1 = by_id(f1, "x")
        inside = np.all((x1 >= lo - margin) & (x1 <= hi + margin), axis=1)
        print(f"{len(gone)} particles left, {len(ids)} remain; left with x0 + U t outside the box: "
              f"{int(outside.sum())}; remaining inside the box + {margin:g}: {int(inside.sum())}")
        ok0 = ok0 and len(gone) > 0 and len(ids) > 0 and bool(outside.all()) and bool(inside.all())
    ok = t > 0 and ok0
    print(f"t = {t:.4g} (step {int(f1['step'][()])}), tolerance {tol:.1e}:")
    for label, value in checks.items():
        good = value <= tol
        ok = ok and good
        print(f"  {label:30s} {value:.3e}  {'ok' if good else 'FAIL'}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
