#!/usr/bin/env python3
"""Symmetric plate impact of an elastic-perfectly-plastic solid in a bar of
coupled particles (uniaxial strain): a flyer at V hits a target of the same
solid at rest at X0 at t = 0, and two waves run into the target, the
elastic precursor at the Hugoniot elastic limit and the plastic shock to the
plateau at V/2 (tools/exact/elastoplastic.py gives both exactly).

    check_particles_hel.py FRAME V RHO0 C0 S1 GAMMA0 G Y X0 H TOL_MEAN TOL_SCATTER TOL_RHO TOL_U TOL_HEL TOL_FRONT

On the target's plateau (the particles more than 6 cells of size H past the
contact and 8 short of the plastic shock): the mean of -sigma_xx against
the exact plateau (relative, TOL_MEAN), its standard deviation (relative,
TOL_SCATTER), the mean density (relative, TOL_RHO) and the largest velocity
error (relative to V/2, TOL_U). On the precursor (6 cells past the
plastic shock to 4 short of the elastic front): the median of -sigma_xx
against the elastic limit's (relative, TOL_HEL). Where -sigma_xx crosses
half way between the two waves' stresses against X0 + Up t and where it
crosses half the elastic limit's against X0 + U1 t (cells, TOL_FRONT).
Prints each value with its bound.
"""
import os
import sys

import h5py
import numpy as np

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "exact"))
from elastoplastic import solve  # noqa: E402


def main():
    frame = sys.argv[1]
    v0, rho0, c0, s1, gamma0, g, y, x0, h = (float(a) for a in sys.argv[2:11])
    tol_mean, tol_scatter, tol_rho, tol_u, tol_hel, tol_front = (float(a) for a in sys.argv[11:17])
    ex = solve(rho0=rho0, c0=c0, s1=s1, gamma0=gamma0, g=g, y=y, v=v0)
    with h5py.File(frame, "r") as f:
        t = float(f["time"][()])
        x = f["particles/x"][()][:, 0]
        u = f["particles/velocity"][()][:, 0]
        s = -f["particles/stress"][()][:, 0]
        rho = f["particles/density"][()]
    order = np.argsort(x, kind="stable")
    x, u, s, rho = x[order], u[order], s[order], rho[order]
    xc = x0 + ex["uf"] * t                # the contact
    xp = x0 + ex["Up"] * t                # the plastic shock
    xe = x0 + ex["U1"] * t                # the elastic precursor
    plateau = (x > xc + 6 * h) & (x < xp - 8 * h)
    precursor = (x > xp + 6 * h) & (x < xe - 4 * h)
    if plateau.sum() < 10 or precursor.sum() < 4:
        print(f"FAIL: too few particles on the plateau ({plateau.sum()}) or the precursor ({precursor.sum()})")
        return 1
    checks = [
        ("plateau mean -sigma_xx / exact - 1", s[plateau].mean() / ex["sigmaf"] - 1.0, tol_mean),
        ("plateau scatter of -sigma_xx / exact", s[plateau].std() / ex["sigmaf"], tol_scatter),
        ("plateau mean density / exact - 1", rho[plateau].mean() / ex["rhof"] - 1.0, tol_rho),
        ("plateau largest |u - V/2| / (V/2)", np.abs(u[plateau] - ex["uf"]).max() / ex["uf"], tol_u),
        ("precursor median -sigma_xx / elastic limit - 1", np.median(s[precursor]) / ex["sigma1"] - 1.0, tol_hel),
    ]
    past = np.nonzero((s > 0.5 * (ex["sigma1"] + ex["sigmaf"])) & (x > xc))[0]
    checks.append(("plastic shock - (X0 + Up t), cells", (x[past[-1]] - xp) / h, tol_front))
    past = np.nonzero((s > 0.5 * ex["sigma1"]) & (x > xc))[0]
    checks.append(("elastic front - (X0 + U1 t), cells", (x[past[-1]] - xe) / h, tol_front))
    print(f"t = {t:.6g}: exact plateau -sigma_xx {ex['sigmaf']:.6g}, rho {ex['rhof']:.6g}, u {ex['uf']:.6g}; "
          f"elastic limit -sigma_xx {ex['sigma1']:.6g}; Up {ex['Up']:.6g}, U1 {ex['U1']:.6g}; "
          f"{plateau.sum()} plateau and {precursor.sum()} precursor particles")
    ok = True
    for name, value, tol in checks:
        good = abs(value) <= tol
        ok = ok and good
        print(f"{'ok  ' if good else 'FAIL'} {name}: {value:+.4g} (bound {tol:g})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
