#!/usr/bin/env python3
"""The ballistic slab's velocity at its last frame against the exact one
(tools/exact/ballistic.py), for runs through Euler steps (issue 34's bar:
within 0.2 % at the end).

    check_particles_slab.py PREFIX P0 RHO0 GAMMA M L TOL

PREFIX_NNNNN.h5 are the frames of a run. The slab's velocity is the
mass-weighted mean particle velocity U = sum_p m_p u_p / sum_p m_p; at the
last frame with t <= valid_until (the reflected rarefaction cannot have
reached the slab) |U/u(t) - 1| must be at most TOL. Run with
/usr/bin/python3 (Debian numpy and h5py).
"""
import glob
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "exact"))
sys.dont_write_bytecode = True
from ballistic import Ballistic  # noqa: E402


def main():
    prefix = sys.argv[1]
    p0, rho0, gamma, m, length, tol = (float(v) for v in sys.argv[2:8])
    exact = Ballistic(p0, rho0, gamma, m, length)
    last = None
    for fn in sorted(glob.glob(prefix + "_[0-9][0-9][0-9][0-9][0-9].h5")):
        with h5py.File(fn, "r") as f:
            t = float(f["time"][()])
            mass = f["particles/mass"][()]
            u = f["particles/velocity"][()][:, 0]
        if 0.0 < t <= exact.valid_until():
            last = (t, float(np.sum(mass * u) / np.sum(mass)))
    if last is None:
        print("FAIL: no frame within the exact solution's validity")
        sys.exit(1)
    t, uu = last
    ue = float(exact.velocity(t))
    rel = uu / ue - 1.0
    print(f"t = {t:.4g}: slab velocity {uu:.6f}, exact {ue:.6f}, {100 * rel:+.3f} % (tolerance {100 * tol:.2f} %)")
    ok = abs(rel) <= tol
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
