#!/usr/bin/python3
"""Checks of the tracers (<name>_tracers.txt) and of the maximum pressure
(&output fields = ..., 'max_pressure') against exact solutions.

    check_tracers.py piston OUTDIR NAME --p-tol TOL [--lagrangian] [--track-tol T]
        the piston-driven shock (tests/decks/tracers_piston*.nml: piston speed
        1 into gas at rest, gamma 1.4, rho 1, p 1): exact shock speed
        D = 0.6 + sqrt(0.36 + 1.4), plateau pressure p2 = 1 + D.
        - every frame's max_pressure is >= its pressure, cell by cell, and
          does not decrease from one frame to the next;
        - in the last frame, behind the shock (from 0.1 past the piston to 3
          cells before the exact shock), max_pressure is p2 within TOL
          (relative); 5 cells or more ahead of the shock it is the initial 1
          within TOL;
        - with --lagrangian: at every frame time the tracers that started on
          nodes (1: node (50,0,0), 2: node (30,1,1)) are those nodes, and
          tracer 3 (inside cell 56) is the trilinear image of its start in
          that cell, to 1e-13 of the box (round-off: the tracer's position is
          the trilinear map of the same node positions);
        - with --track-tol T: each tracer follows the exact particle path
          x0 (before the shock reaches it), x0 + (t - x0/D) after, within T
          (length): the scheme's smeared shock passes a point over a few
          cells, which shifts the path by a fraction of a cell.
    check_tracers.py translate OUTDIR NAME UX UY UZ
        a uniform flow at velocity U through a grid brought back to the box
        after every step: every tracer moves by U t. The bound: per step the
        Lagrangian move is exact but for the rounding of x + u dt (a few ulps
        of |x|) and the relocation leaves at most Newton's residual, 1e-14 of
        the cell's size (mesh_geometry `natural_step`), so after N steps the
        error is below N (1e-14 h + 4 eps |x|max); the steps are read from
        the log.
Exit status 0 when every check passes.
"""
import glob
import math
import re
import sys

import h5py
import numpy as np

ok = True


def check(label, value, bound, cond=None):
    global ok
    good = value <= bound if cond is None else cond
    ok &= bool(good)
    print(f"{'ok  ' if good else 'FAIL'} {label}: {value:.3e} (bound {bound:.3e})")


def frames(outdir, name):
    paths = sorted(glob.glob(f"{outdir}/{name}_[0-9][0-9][0-9][0-9][0-9].h5"))
    if not paths:
        sys.exit(f"FAIL: no frames {outdir}/{name}_NNNNN.h5")
    return paths


def tracers(outdir, name):
    path = f"{outdir}/{name}_tracers.txt"
    with open(path) as f:
        head = [line for line in f if line.startswith("#")]
    cols = head[-1].split()[1:]
    starts = [list(map(float, line.split()[4:7])) for line in head if line.startswith("# tracer ")]
    data = np.loadtxt(path, ndmin=2)
    if data.shape[1] != len(cols) or cols[0] != "time" or (len(cols) - 1) % 5 != 0:
        sys.exit(f"FAIL: {path}: the columns do not match the header {cols}")
    n = (len(cols) - 1) // 5
    print(f"{path}: {data.shape[0]} rows, {n} tracers")
    return data, np.array(starts), n


def frame_row(data, t):
    """The tracer row written at the frame's time (the same step)."""
    k = np.argmin(np.abs(data[:, 0] - t))
    if data[k, 0] != t:
        sys.exit(f"FAIL: no tracer row at the frame time {t!r} (nearest {data[k, 0]!r})")
    return data[k]


def piston(outdir, name, p_tol, lagrangian, track_tol):
    D = 0.6 + math.sqrt(0.36 + 1.4)
    p2 = 1.0 + D
    paths = frames(outdir, name)
    prev = None
    worst_drop, worst_below, worst_ahead, n_ahead = 0.0, 0.0, 0.0, 0
    for path in paths:
        with h5py.File(path, "r") as f:
            pm = f["max_pressure"][()].ravel()
            p = f["pressure"][()].ravel()
            tf = float(f["time"][()])
            xf = f["x"][()]
        worst_below = max(worst_below, float(np.max(p - pm)))
        # (5 cells or more ahead of the exact shock: the gas at rest)
        ahead = 0.5 * (xf[0, 0, :-1, 0] + xf[0, 0, 1:, 0]) > D * tf + 5.0 / pm.size
        if tf > 0 and ahead.any():
            worst_ahead = max(worst_ahead, float(np.abs(pm[ahead] - 1.0).max()))
            n_ahead += 1
        if prev is not None:
            worst_drop = max(worst_drop, float(np.max(prev - pm)))
        prev = pm
    check(f"max_pressure - pressure < 0 in all {len(paths)} frames (largest pressure - max_pressure)",
          worst_below, 0.0)
    check("max_pressure non-decreasing from frame to frame (largest drop)", worst_drop, 0.0)
    with h5py.File(paths[-1], "r") as f:
        t = float(f["time"][()])
        x = f["x"][()]
        pm = f["max_pressure"][()].ravel()
    xc = 0.5 * (x[0, 0, :-1, 0] + x[0, 0, 1:, 0])
    h0 = 1.0 / pm.size
    behind = (xc > t + 0.1) & (xc < D * t - 3 * h0)
    dev = np.abs(pm[behind] / p2 - 1.0)
    print(f"t = {t}: exact plateau p2 = {p2:.6f}; max_pressure behind the shock in "
          f"[{pm[behind].min():.6f}, {pm[behind].max():.6f}] over {behind.sum()} cells")
    check("max_pressure behind the shock, largest |p_max/p2 - 1|", float(dev.max()), p_tol)
    check(f"max_pressure ahead of the shock in {n_ahead} frames, largest |p_max - 1|", worst_ahead, p_tol,
          n_ahead > 0 and worst_ahead <= p_tol)
    data, starts, n = tracers(outdir, name)
    if lagrangian:
        worst = 0.0
        for path in paths:
            with h5py.File(path, "r") as f:
                tf = f["time"][()]
                xn = f["x"][()]                       # (k, j, i, 3)
            row = frame_row(data, tf)
            pos = row[1:].reshape(n, 5)[:, :3]
            worst = max(worst, np.abs(pos[0] - xn[0, 0, 50]).max(), np.abs(pos[1] - xn[1, 1, 30]).max())
            # tracer 3: its start in cell 56 (nodes 55, 56), trilinear image
            lo, hi = np.array([0.55, 0.0, 0.0]), np.array([0.56, 0.01, 0.01])
            w = (starts[2] - lo) / (hi - lo)
            a, b = xn[0, 0, 55], xn[1, 1, 56]        # (the cell is an axis-aligned box in 1D)
            worst = max(worst, np.abs(pos[2] - (a + w * (b - a))).max())
        check(f"Lagrangian tracers on their nodes / trilinear images over {len(paths)} frames (length)",
              worst, 1e-13)
    if track_tol is not None:
        worst = 0.0
        for k in range(n):
            x0 = starts[k][0]
            tt = data[:, 0]
            exact = np.where(tt < x0 / D, x0, x0 + (tt - x0 / D))
            worst = max(worst, float(np.abs(data[:, 1 + 5 * k] - exact).max()))
            # (no transverse motion in this 1D flow)
            worst_t = float(np.abs(data[:, 2 + 5 * k:4 + 5 * k] - starts[k][1:]).max())
            check(f"tracer {k + 1} transverse drift (length)", worst_t, 1e-12)
        check("tracers against the exact particle paths, largest |x - x_exact| (length)", worst, track_tol)


def translate(outdir, name, u):
    data, starts, n = tracers(outdir, name)
    with open(f"{outdir}/{name}.log") as f:
        m = re.findall(r"done: t = \S+ after (\d+) steps", f.read())
    steps = int(m[-1])
    with h5py.File(frames(outdir, name)[0], "r") as f:
        xn = f["x"][()]
    h = float(np.max(np.linalg.norm(xn[1:, 1:, 1:] - xn[:-1, :-1, :-1], axis=-1)))
    xmax = float(np.abs(xn).max())
    bound = steps * (1e-14 * h + 4 * np.finfo(float).eps * xmax)
    worst = 0.0
    for k in range(n):
        pos = data[:, 1 + 5 * k:4 + 5 * k]
        exact = starts[k] + np.outer(data[:, 0], u)
        worst = max(worst, float(np.abs(pos - exact).max()))
    print(f"{steps} steps (an Euler step each), cell diagonal {h:.3g}, final time {data[-1, 0]}")
    check(f"{n} tracers moved by U t, largest |x - x0 - U t| (length)", worst, bound)
    moved = float(np.abs(data[-1, 1:].reshape(n, 5)[:, :3] - starts).max())
    check("the tracers moved (largest displacement, length, must be > 0.5)", 0.5, moved, moved > 0.5)


def main():
    a = sys.argv[1:]
    if len(a) >= 3 and a[0] == "piston":
        p_tol = float(a[a.index("--p-tol") + 1])
        track = float(a[a.index("--track-tol") + 1]) if "--track-tol" in a else None
        piston(a[1], a[2], p_tol, "--lagrangian" in a, track)
    elif len(a) == 6 and a[0] == "translate":
        translate(a[1], a[2], np.array(list(map(float, a[3:6]))))
    else:
        sys.exit(__doc__)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
