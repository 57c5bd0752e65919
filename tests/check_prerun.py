#!/usr/bin/env python3
"""The 1D spherical pre-run (&prerun) mapped into the grid.

    check_prerun.py conservation OUT/NAME [DENSITY_L1]
    check_prerun.py continued PROFILE_1D OUT_COARSE/NAME OUT_FINE/NAME
    check_prerun.py zones PROFILE_1D SPHERE_RADIUS FAR_ZONE_WIDTH
    check_prerun.py merge LOG_UNMERGED LOG_MERGED

conservation: from the run's log, the mapping gave the cells the 1D run's
mass, total energy and radial momentum within the mapped radius (times the
part of a sphere in the grid), each to 1e-13 relative (exact sums of the
scaled overlaps: round-off); the grid's initial mass and total energy are
what the 1D run and the regions gave, to 1e-13 (the nodes' kinetic energy was
taken from the cells' internal energy); from frame 0, the nodes' radial
momentum sum_n m_n u_n . (x_n - c)/|x_n - c| is the 1D run's to 1e-12. Frame
0's density is the 1D zones' (piecewise constant) averaged over each cell
(32^3 points a cell), L1 relative to the profile's departure from ambient
below 5e-3: measured at 12^3 1.1e-2, 2.8e-3 and 8.1e-4 with 4, 8 (the
default) and 16 subsamples, the overlaps' error (a sub-box's volume spread
evenly over its span of radii) falling about as the sub-box's width squared
(DENSITY_L1 gives another bound: the charge in water, whose density departs
little from ambient so that the relative L1 is larger, measured 7.2e-3 at
12^3, is checked against 1e-2).

continued: the last frame of the mapped run (12^3 and 24^3), against the 1D
run continued to the same time (PROFILE_1D): the pressure's L1 relative to
the profile's departure from ambient, over the grid. A captured shock in 3D
at 5 and 2.5 mm cells against a 1D run at 0.05 mm zones: measured 0.99 and
0.45; the test asks for first-order convergence (fine <= 0.6 coarse) and
coarse <= 1.2.

zones: the 1D zones beyond the outermost sphere that the run has not
disturbed (pressure at its initial value: they have their initial widths)
never get wider as they go out, are at most FAR_ZONE_WIDTH wide (to 1e-9),
and the outermost is at least 0.9 of it (the cap reached: uniform zones of
about that width, each of (radius - r_cap)/n).

merge: the logs of the same 1D run without zone merges (merge_ratio = 0)
and with them (the default): each run's total energy conserved to 1e-13
relative (merges move the kinetic energy they take into internal energy),
the merged run made merges and took at most a tenth of the steps (the thin
hot shell no longer sets the step: measured 1/21.6), and at every gauge the
arrival agrees to 1e-4 relative, the peak overpressure and the positive
impulse to 1 % (the merges coarsen only the fireball's hot air behind the
contact, far behind the blast front; measured 3e-6, 0.41 % and 0.01 %).
"""
import glob
import re
import sys

import h5py
import numpy as np


def profile(path):
    """Zone centres, densities, pressures and outer radii of a 1D profile."""
    d = np.genfromtxt(path, usecols=range(8))
    return d[:, 2], d[:, 3], d[:, 5], d[:, 1]


def frame(prefix, index):
    return h5py.File(sorted(glob.glob(prefix + "_0*.h5"))[index], "r")


def cell_average(f, r1, v1, n=4, zones=None):
    """v1 at radii r1 averaged over each cell at n^3 points: linear between
    the radii, or with zones (the zones' outer radii) piecewise constant."""
    x = f["x"][()]
    lo, hi = x[:-1, :-1, :-1], x[1:, 1:, 1:]
    s = (np.arange(n) + 0.5) / n
    acc = 0.0
    for a in s:
        for b in s:
            for c in s:
                pt = lo + (hi - lo) * np.array([a, b, c])
                r = np.sqrt((pt ** 2).sum(-1))
                if zones is None:
                    acc = acc + np.interp(r, r1, v1)
                else:
                    acc = acc + v1[np.minimum(np.searchsorted(zones, r), len(v1) - 1)]
    return acc / n**3


def l1(f, field, r1, v1, n=4, zones=None):
    avg = cell_average(f, r1, v1, n, zones)
    vol = f["volume"][()]
    return (np.abs(f[field][()] - avg) * vol).sum() / (np.abs(avg - v1[-1]) * vol).sum()


def conservation(prefix, density_tol=5e-3):
    log = open(prefix + ".log").read()
    num = r"([-+0-9.Ee]+)"
    m = re.search(r"prerun: mapped mass " + num + ", total energy " + num + ", radial momentum " + num +
                  r" \(the 1D run's within the mapped radius: " + num + ", " + num + ", " + num +
                  r"\); the regions' part: mass " + num + ", energy " + num, log)
    a_m, a_e, a_p, d_m, d_e, d_p, r_m, r_e = map(float, m.groups())
    bad = 0
    for what, got, want, tol in (("mass", a_m, d_m, 1e-13), ("total energy", a_e, d_e, 1e-13),
                                 ("radial momentum", a_p, d_p, 1e-13)):
        rel = abs(got - want) / abs(want)
        print(f"mapped {what}: {got:.16e} vs the 1D run's {want:.16e}: relative {rel:.2e} (<= {tol:g})")
        bad += rel > tol
    g_m = float(re.search(r"conservation \(initial\): mass\s+" + num, log).group(1))
    g_e = float(re.search(r"conservation \(initial\):.*\n\s+energy: internal\s+\S+\s+kinetic\s+\S+\s+total\s+" + num,
                          log).group(1))
    for what, got, want in (("mass", g_m, a_m + r_m), ("total energy", g_e, a_e + r_e)):
        rel = abs(got - want) / abs(want)
        print(f"grid {what} {got:.16e} vs mapped + regions {want:.16e}: relative {rel:.2e} (<= 1e-13)")
        bad += rel > 1e-13
    f = frame(prefix, 0)
    x = f["x"][()].reshape(-1, 3)
    u = f["velocity"][()].reshape(-1, 3)
    mn = f["node_mass"][()].reshape(-1)
    r = np.sqrt((x ** 2).sum(1))
    ok = r > 0
    p_rad = (mn[ok] * (u[ok] * x[ok]).sum(1) / r[ok]).sum()
    rel = abs(p_rad - d_p) / d_p
    print(f"nodes' radial momentum {p_rad:.16e} vs the 1D run's {d_p:.16e}: relative {rel:.2e} (<= 1e-12)")
    bad += rel > 1e-12
    r1, rho1, _, rout = profile(prefix + "_prerun.txt")
    e = l1(f, "density", r1, rho1, 32, rout)
    print(f"frame 0 density against the 1D zones averaged over the cells: L1 {e:.2e} (<= {density_tol:g})")
    bad += e > density_tol
    return bad


def continued(path_1d, coarse, fine):
    r1, _, p1, _ = profile(path_1d)
    e = []
    for prefix in (coarse, fine):
        f = frame(prefix, -1)
        e.append(l1(f, "pressure", r1, p1))
        print(f"{prefix} at t = {f['time'][()]}: pressure L1 against the 1D run continued {e[-1]:.3f}")
    bad = (e[1] > 0.6 * e[0]) + (e[0] > 1.2)
    print(f"ratio fine/coarse {e[1] / e[0]:.3f} (<= 0.6), coarse {e[0]:.3f} (<= 1.2)")
    return bad


def zones(path_1d, sphere, far):
    d = np.genfromtxt(path_1d, usecols=range(8))
    p = d[:, 5]
    quiet = np.nonzero(np.abs(p - p[-1]) > 1e-6 * abs(p[-1]))[0][-1] + 1
    r_in, r_out = d[quiet:, 0], d[quiet:, 1]
    keep = r_in >= float(sphere)
    w = (r_out - r_in)[keep]
    far = float(far)
    print(f"{w.size} undisturbed zones beyond the sphere: widths {w.min():.4g} to {w.max():.4g}, "
          f"outermost {w[-1]:.4g}, far_zone_width {far:g}")
    bad = int(w.size < 10)
    bad += int(np.any(np.diff(w) < -1e-9 * far))
    bad += int(w.max() > far * (1 + 1e-9))
    bad += int(w[-1] < 0.9 * far)
    return bad


def prerun_log(path):
    """(relative energy change, steps, merges, {gauge: (arrival, peak, impulse)})."""
    text = open(path).read()
    m = re.search(r"relative change (\S+)\); (\d+) steps, (\d+) zone merges", text)
    gauges = {}
    for g in re.finditer(r"prerun gauge (\d+) .*?: arrival (\S+), peak overpressure (\S+), "
                         r"positive duration \S+, positive impulse ([0-9.Ee+-]+)", text):
        gauges[int(g.group(1))] = tuple(float(g.group(k)) for k in (2, 3, 4))
    return float(m.group(1)), int(m.group(2)), int(m.group(3)), gauges


def merge(log0, log1):
    e0, s0, n0, g0 = prerun_log(log0)
    e1, s1, n1, g1 = prerun_log(log1)
    print(f"unmerged: {s0} steps, {n0} merges, energy change {e0:.2e}; merged: {s1} steps, {n1} merges, "
          f"energy change {e1:.2e}; steps ratio {s1 / s0:.4f} (<= 0.1)")
    bad = int(abs(e0) > 1e-13) + int(abs(e1) > 1e-13) + int(n0 != 0) + int(n1 == 0) + int(s1 > 0.1 * s0)
    bad += int(not g0 or sorted(g0) != sorted(g1))
    for k in sorted(g0):
        (a0, p0, i0), (a1, p1, i1) = g0[k], g1.get(k, (np.nan,) * 3)
        da, dp, di = abs(a1 / a0 - 1), abs(p1 / p0 - 1), abs(i1 / i0 - 1)
        print(f"gauge {k}: arrival {a0:.6g} / {a1:.6g} ({da:.1e} <= 1e-4), peak {p0:.6g} / {p1:.6g} ({dp:.2%} <= 1 %), "
              f"impulse {i0:.6g} / {i1:.6g} ({di:.2%} <= 1 %)")
        bad += int(not da <= 1e-4) + int(not dp <= 0.01) + int(not di <= 0.01)
    return bad


if __name__ == "__main__":
    if sys.argv[1] == "conservation":
        bad = conservation(sys.argv[2], *map(float, sys.argv[3:4]))
    elif sys.argv[1] == "zones":
        bad = zones(*sys.argv[2:5])
    elif sys.argv[1] == "merge":
        bad = merge(*sys.argv[2:4])
    else:
        bad = continued(*sys.argv[2:5])
    sys.exit(1 if bad else 0)
