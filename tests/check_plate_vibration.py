#!/usr/bin/env python3
"""The first peak of a clamped plate's free vibration against Euler-Bernoulli.

    check_plate_vibration.py TRACKS E NU RHO THICKNESS LENGTH TOL

TRACKS: the run's <name>_tracks.txt, whose first track is a particle at the
plate's free end, started (with the whole plate) at a uniform velocity
along x from rest in bending. Its x displacement peaks a quarter of the
first period later (the run ends before the second peak); plane strain (E' = E / (1 - NU^2)):

    T = 2 pi / (1.875^2 sqrt(E' d^2 / (12 RHO L^4))).

Checks the peak time against T / 4 (relative, TOL). Shear and rotary
inertia (Timoshenko) lengthen a plate of slenderness 20 by well under 1 %;
the bound is for the discretisation.
"""
import math
import sys

import numpy as np


def main():
    path = sys.argv[1]
    e, nu, rho, d, length, tol = (float(a) for a in sys.argv[2:8])
    data = np.loadtxt(path)
    t, x = data[:, 0], data[:, 2] - data[0, 2]
    period = 2.0 * math.pi / (1.875**2 * math.sqrt(e / (1.0 - nu**2) * d**2 / (12.0 * rho * length**4)))
    i = int(np.argmax(x))
    if i == len(x) - 1:
        print(f"FAIL no peak of the x displacement by t = {t[-1]:.3f} (T/4 = {period / 4:.3f})")
        return 1
    err = t[i] / (period / 4.0) - 1.0
    status = "ok  " if abs(err) <= tol else "FAIL"
    print(f"{status} first peak {x[i]:.5f} at t = {t[i]:.3f}; T/4 = {period / 4:.3f} (Euler-Bernoulli): "
          f"{err:+.4f} (bound {tol})")
    return 0 if abs(err) <= tol else 1


if __name__ == "__main__":
    sys.exit(main())
