#!/usr/bin/env python3
"""Symmetric plate impact in a bar of coupled particles (uniaxial strain): a
flyer at V hits a target of the same solid at rest at X0 at t = 0. With a
Mie-Gruneisen solid of no strength two shocks run out of the contact; by
symmetry the material between them moves at up = V/2, and the jump
conditions with Us = c0 + s1 up give

    sigma_xx = -rho0 Us up,   the target's shock at X0 + Us t,
                              the flyer's at X0 + (V - Us) t.

    check_particles_impact.py FRAME V RHO0 C0 S1 X0 H TOL_MEAN TOL_SCATTER TOL_U TOL_FRONT TOL_CONTACT

Over the particles of both shocked plateaux (those within 6 cells of the
contact and 8 of either shock left out, cells of size H), checks the mean of
-sigma_xx against rho0 Us up (relative, TOL_MEAN), its standard deviation
(relative, TOL_SCATTER), the largest velocity error (relative to up,
TOL_U); where -sigma_xx crosses half the plateau on the target's shock
against X0 + Us t (in cells of size H, TOL_FRONT); and the particles within
4 cells of the contact against the plateau (largest relative deviation,
TOL_CONTACT: two bodies that meet at a node must not leave a spurious
compression or tension there). Prints each value with its bound.
"""
import sys

import h5py
import numpy as np


def main():
    frame = sys.argv[1]
    v0, rho0, c0, s1, x0, h = (float(a) for a in sys.argv[2:8])
    tol_mean, tol_scatter, tol_u, tol_front, tol_contact = (float(a) for a in sys.argv[8:13])
    with h5py.File(frame, "r") as f:
        t = float(f["time"][()])
        x = f["particles/x"][()][:, 0]
        u = f["particles/velocity"][()][:, 0]
        s = -f["particles/stress"][()][:, 0]
    order = np.argsort(x, kind="stable")
    x, u, s = x[order], u[order], s[order]
    up = 0.5 * v0
    us = c0 + s1 * up
    p = rho0 * us * up
    xc = x0 + up * t                     # the contact
    xs = x0 + us * t                     # the target's shock
    xb = x0 + (v0 - us) * t              # the flyer's shock
    target = (x > xc + 6 * h) & (x < xs - 8 * h)
    flyer = (x < xc - 6 * h) & (x > xb + 8 * h)
    plateau = target | flyer
    if target.sum() < 10 or flyer.sum() < 10:
        print(f"FAIL: too few particles on the plateaux ({target.sum()}, {flyer.sum()}) at t = {t}")
        return 1
    exact_u = np.where(x > xc, up, v0 - up)
    checks = [
        ("mean -sigma_xx / exact - 1", s[plateau].mean() / p - 1.0, tol_mean),
        ("scatter of -sigma_xx / exact", s[plateau].std() / p, tol_scatter),
        ("largest |u - exact| / up", np.abs(u[plateau] - exact_u[plateau]).max() / up, tol_u),
    ]
    ahead = np.nonzero((s > 0.5 * p) & (x > xc))[0]
    checks.append(("target shock - (X0 + Us t), cells", (x[ahead[-1]] - xs) / h, tol_front))
    near = np.abs(x - xc) < 4 * h
    checks.append(("largest |-sigma_xx / exact - 1| at the contact", np.abs(s[near] / p - 1.0).max(), tol_contact))
    print(f"t = {t:.6g}: up = {up:.6g}, Us = {us:.6g}, -sigma_xx = {p:.6g}; "
          f"{plateau.sum()} plateau particles, {near.sum()} at the contact")
    ok = True
    for name, value, tol in checks:
        good = abs(value) <= tol
        ok = ok and good
        print(f"{'ok  ' if good else 'FAIL'} {name}: {value:+.4g} (bound {tol:g})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
