#!/usr/bin/env python3
"""Ringing behind the two elastic fronts of the elastic Riemann problem in a
bar of particles (uniaxial strain, jump at X0 from SIGMA_L to SIGMA_R, wave
speed C = sqrt(M/rho); between the fronts sigma* = (SIGMA_L + SIGMA_R)/2),
at two resolutions.

    check_particles_ringing.py COARSE FINE SIGMA_L SIGMA_R C X0 AREA MAX_OVERSHOOT

For each frame: the overshoot of sigma_xx past sigma* between each front and
X0 (the particles with X0 < x < X0 + C t for the right-going front, X0 - C t
< x < X0 for the left-going one), in units of |sigma* - SIGMA_R| (=
|sigma* - SIGMA_L|), must be at most MAX_OVERSHOOT; and the L1 error of
sigma_xx against the exact profile, sum |sigma_p - exact(x_p)| V_p / AREA,
must fall from COARSE to FINE. Prints every number.
"""
import os
import sys

import h5py
import numpy as np


def measure(frame, sl, sr, c, x0, area):
    """(overshoot left, overshoot right, L1, t) of one frame."""
    with h5py.File(frame, "r") as f:
        t = float(f["time"][()])
        px = f["particles/x"][()][:, 0]
        s = f["particles/stress"][()][:, 0]
        vol = f["particles/volume"][()]
    star = 0.5 * (sl + sr)
    jump = abs(star - sr)
    exact = np.where(px < x0 - c * t, sl, np.where(px < x0 + c * t, star, sr))
    l1 = np.sum(np.abs(s - exact) * vol) / area
    sgn = np.sign(star - sr)      # the right-going front moves sigma from sr towards star
    right = (px > x0) & (px < x0 + c * t)
    left = (px < x0) & (px > x0 - c * t)
    over_r = max(0.0, np.max(sgn * (s[right] - star))) / jump
    over_l = max(0.0, np.max(-sgn * (s[left] - star))) / jump
    return over_l, over_r, l1, t


def main():
    coarse, fine = sys.argv[1:3]
    sl, sr, c, x0, area, max_over = (float(v) for v in sys.argv[3:9])
    ok = True
    l1s = []
    for frame in (coarse, fine):
        ol, orr, l1, t = measure(frame, sl, sr, c, x0, area)
        good = ol <= max_over and orr <= max_over
        ok = ok and good
        l1s.append(l1)
        print(f"{os.path.basename(frame)}: t = {t:.6g}, overshoot left {ol:.4f}, right {orr:.4f} of the jump "
              f"(at most {max_over}), L1 of sigma_xx {l1:.4e}  {'ok' if good else 'FAIL'}")
    good = l1s[1] < l1s[0]
    ok = ok and good
    print(f"L1 coarse / fine = {l1s[0] / l1s[1]:.3f} (order {np.log2(l1s[0] / l1s[1]):.2f}; must exceed 1)  "
          f"{'ok' if good else 'FAIL'}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
