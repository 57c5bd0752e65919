#!/usr/bin/env python3
"""Lagrange ballistic problem (PARTICLES.md section 4, rung 5) against the
exact slab velocity of tools/exact/ballistic.py, at two resolutions.

    check_particles_ballistic.py COARSE_PREFIX FINE_PREFIX P0 RHO0 GAMMA M L \\
        MAX_COARSE MAX_FINE RATIO_MIN [RATIO_MAX_MIN]

PREFIX_NNNNN.h5 are the frames of a run. In every frame with
0 < t <= valid_until (the reflected rarefaction cannot have reached the
slab), the slab's velocity is the mass-weighted mean particle velocity
U = sum_p m_p u_p / sum_p m_p (the elastic slab rings; its mean velocity
follows the pressures on its faces); the largest |U - u(t)| over the
frames must be below MAX_COARSE / MAX_FINE, and the RMS over the frames
must fall by at least RATIO_MIN from coarse to fine, the largest by at
least RATIO_MAX_MIN (default RATIO_MIN: the largest is one frame's phase of
the ringing, a noisier measure of the order). Also
checks that the particles' mass per unit cross-section is M (1e-12).
"""
import glob
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "exact"))
sys.dont_write_bytecode = True
from ballistic import Ballistic  # noqa: E402


def slab_errors(prefix, exact, areal_mass):
    """(max |U - u|, RMS, frames used, areal mass ok) over a run's frames."""
    frames = sorted(glob.glob(prefix + "_[0-9][0-9][0-9][0-9][0-9].h5"))
    if not frames:
        sys.exit(f"FAIL: no frames {prefix}_NNNNN.h5")
    t_max = exact.valid_until()
    err = []
    mass_ok = True
    for fn in frames:
        with h5py.File(fn, "r") as f:
            t = float(f["time"][()])
            m = f["particles/mass"][()]
            u = f["particles/velocity"][()][:, 0]
            x = f["x"][()]
        area = (x[0, 1, 0, 1] - x[0, 0, 0, 1]) * (x[1, 0, 0, 2] - x[0, 0, 0, 2])
        mass_ok = mass_ok and abs(m.sum() / area - areal_mass) <= 1e-12 * areal_mass
        if 0.0 < t <= t_max:
            err.append(np.sum(m * u) / np.sum(m) - float(exact.velocity(t)))
    err = np.array(err)
    if err.size == 0:
        sys.exit(f"FAIL: no frame of {prefix} with 0 < t <= {t_max:.4g}")
    k = int(np.argmax(np.abs(err)))
    return float(np.abs(err[k])), float(np.sqrt(np.mean(err ** 2))), err.size, mass_ok


def main():
    coarse, fine = sys.argv[1:3]
    p0, rho0, gamma, areal_mass, length = (float(v) for v in sys.argv[3:8])
    bounds = (float(sys.argv[8]), float(sys.argv[9]))
    ratio_min = float(sys.argv[10])
    ratio_max_min = float(sys.argv[11]) if len(sys.argv) > 11 else ratio_min
    exact = Ballistic(p0, rho0, gamma, areal_mass, length)
    print(f"exact: c0 = {exact.c0:.6g}, escape speed {1.0 / exact.a:.6g}, valid until t = {exact.valid_until():.4g}")
    ok = True
    res = []
    for prefix, bound in zip((coarse, fine), bounds):
        emax, erms, n, mass_ok = slab_errors(prefix, exact, areal_mass)
        res.append((emax, erms))
        good = emax <= bound and mass_ok
        ok = ok and good
        print(f"{os.path.basename(prefix)}: {n} frames, max |U - u| {emax:.4e} (bound {bound:.1e}), RMS {erms:.4e},"
              f" areal mass {'ok' if mass_ok else 'WRONG'}  {'ok' if good else 'FAIL'}")
    for k, (name, least) in enumerate((("max", ratio_max_min), ("RMS", ratio_min))):
        ratio = res[0][k] / res[1][k]
        good = ratio >= least
        ok = ok and good
        print(f"{name} error coarse / fine = {ratio:.3f} (at least {least})  {'ok' if good else 'FAIL'}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
