#!/usr/bin/env python3
"""Elastic Riemann problem in a bar of coupled particles (uniaxial strain):
two elastic waves run out of a stress jump at X0 at c = sqrt(M/rho); between
them (linear elasticity, Riemann invariants sigma -/+ rho c u along +/-c)

    u* = (sigma_R - sigma_L) / (2 rho c),   sigma* = (sigma_L + sigma_R) / 2.

    check_particles_riemann.py FRAME RHO M SIGMA_L SIGMA_R X0 H TOL_U TOL_S TOL_FRONT

Checks, over the particles within 0.1 of X0: the median x-velocity against
u* (relative TOL_U) and the median sigma_xx against sigma* (relative to
|sigma_R - sigma_L|, TOL_S); and where the velocity profile crosses u*/2
(linear interpolation between particles) against X0 -/+ c t, in cells of
size H (TOL_FRONT). Prints each value, the exact value and the tolerance.
"""
import sys

import h5py
import numpy as np


def crossing(x, u, level, left):
    """x where u crosses level on the rising (left) or falling (right) edge."""
    above = np.nonzero(u > level)[0]
    i = above[0] if left else above[-1]
    j = i - 1 if left else i + 1
    return x[j] + (level - u[j]) * (x[i] - x[j]) / (u[i] - u[j])


def main():
    frame = sys.argv[1]
    rho, modulus, s_l, s_r, x0, h, tol_u, tol_s, tol_f = (float(v) for v in sys.argv[2:11])
    with h5py.File(frame, "r") as f:
        t = float(f["time"][()])
        x = f["particles/x"][()][:, 0]
        u = f["particles/velocity"][()][:, 0]
        sxx = f["particles/stress"][()][:, 0]
    order = np.argsort(x, kind="stable")
    x, u, sxx = x[order], u[order], sxx[order]
    c = np.sqrt(modulus / rho)
    u_star = (s_r - s_l) / (2.0 * rho * c)
    s_star = 0.5 * (s_l + s_r)
    mid = np.abs(x - x0) < 0.1
    checks = [
        ("plateau velocity / u* - 1", np.median(u[mid]) / u_star - 1.0, tol_u),
        ("plateau sigma_xx - sigma* (per jump)", (np.median(sxx[mid]) - s_star) / abs(s_r - s_l), tol_s),
        ("left front - (X0 - c t) (cells)", (crossing(x, u, 0.5 * u_star, True) - (x0 - c * t)) / h, tol_f),
        ("right front - (X0 + c t) (cells)", (crossing(x, u, 0.5 * u_star, False) - (x0 + c * t)) / h, tol_f),
    ]
    print(f"t = {t:.4g}, c = {c:.6g}, u* = {u_star:.6g}, sigma* = {s_star:.6g}")
    ok = True
    for label, value, tol in checks:
        good = abs(value) <= tol
        ok = ok and good
        print(f"  {label:40s} {value:+.3e}  tolerance {tol:.1e}  {'ok' if good else 'FAIL'}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
