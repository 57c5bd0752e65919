#!/usr/bin/env python3
"""The Taylor bar (PARTICLES.md §2.7 anchor 1, input/taylor_bar.nml): final
length, mushroom (foot) diameter, largest plastic strain and temperature
from the particles of the last frame of a run.

    taylor_measure.py OUTDIR [OUTDIR ...] [--axis z] [--ref L D] [--tol-l 0.01] [--tol-d 0.03]

Each OUTDIR holds the HDF5 frames of one run of a quarter model whose bar
stands on the plane axis = 0 (the rigid wall) with its axis along the
grid's `axis` through the line where the two symmetry planes (the other two
coordinates = 0) meet. Particles are the centres of their volumes, so the
material reaches beyond the outermost centre; two estimates of how far:

  L_f  = max over particles of (a + h_p), a the coordinate along the axis,
         h_p = V_p^(1/3)/2 the half-width of the cube of the particle's
         current volume (the top end is hardly strained: the cube is right);
  D_f  = the bottom layer's two rows along the symmetry planes (identified
         in the first frame, followed by particle id): each row's outer end
         is its last centre plus half the distance to the one before (the
         rim particles are flattened and stretched, so their cube would be
         wrong; their neighbour distance is not), D_f = the sum of the two
         radii (twice their mean).

Also printed, to show how much the surface estimate matters: the centres
only (L_ctr, D_ctr along the planes), D_pl (the rows along the planes, any
layer, with the half-width h_p), D_all (all directions, with h_p; it
includes a corner of the seeding's staircase: at spacing 0.4 the initial
diameter reads 6.72 instead of 6.4), the same L and D of the first frame
(L0, D0: 32.4 and 6.4 when the particle spacing divides the bar's length
and radius; otherwise the seeding made the bar that much longer) and
L_corr = L_f - (L0 - 32.4); the largest 'plastic_strain' and 'temperature'
(the model's fields). Errors are against --ref (default DynELA: L_f 26.52
mm, D_f 11.15 mm); the exit status is 1 if any run misses --tol-l or
--tol-d (relative), 0 otherwise. Run with /usr/bin/python3 (h5py, numpy).
"""
import argparse
import glob
import os
import sys

import h5py
import numpy as np

REFS = {"DynELA": (26.52, 11.15, 1.78, 582.0), "Abaqus": (26.56, 11.16, 1.81, 591.0)}


def read_frame(path):
    """Positions (n, 3), volumes, ids, time, plastic strain and temperature."""
    with h5py.File(path, "r") as f:
        missing = [n for n in ("particles/x", "particles/volume", "particles/id") if n not in f]
        if missing:
            sys.exit(f"{path}: no {', '.join(missing)} (the deck's &output particle_fields must include "
                     f"'volume' and 'id')")
        x = f["particles/x"][()]
        vol = f["particles/volume"][()]
        ids = f["particles/id"][()]
        t = float(f["time"][()])
        epsp = f["particles/plastic_strain"][()] if "particles/plastic_strain" in f else np.zeros(len(vol))
        temp = f["particles/temperature"][()] if "particles/temperature" in f else np.zeros(len(vol))
    if x.shape[0] != len(vol):
        x = x.T
    return x, vol, ids, t, epsp, temp


def edge(x_row, key):
    """The outer end of a row of particles ordered by key (initial
    coordinate): the last centre plus half its distance to the one before."""
    order = np.argsort(key)
    last, prev = x_row[order[-1]], x_row[order[-2]]
    return last + 0.5 * (last - prev)


def measure(outdir, axis, which=-1):
    """Dictionary of the measures (module notes) of the last frame (which =
    -1) or the first (which = 0); rows and layers from the first frame's
    positions, matched by particle id."""
    frames = sorted(glob.glob(os.path.join(outdir, "*.h5")))
    if not frames:
        sys.exit(f"{outdir}: no HDF5 frames")
    x0, vol0, id0, _, _, _ = read_frame(frames[0])
    x, vol, ids, t, epsp, temp = read_frame(frames[which])
    # the first frame's positions in the order of this frame's particles
    x0 = x0[np.argsort(id0)][np.searchsorted(np.sort(id0), ids)]
    others = [d for d in range(3) if d != axis]
    a, o1, o2 = x[:, axis], x[:, others[0]], x[:, others[1]]
    a0, p1, p2 = x0[:, axis], x0[:, others[0]], x0[:, others[1]]
    h = 0.5 * np.cbrt(vol)
    sp = float(np.median(np.cbrt(vol0)))          # the seeding's spacing
    r = np.hypot(o1, o2)
    rows1, rows2 = o1 < 2.0 * h, o2 < 2.0 * h
    b = np.concatenate([o2[rows1], o1[rows2]])
    hb = np.concatenate([h[rows1], h[rows2]])
    # neighbour measures: the axis row (first row along both planes), the
    # bottom layer's rows along the two planes
    axis_row = (p1 < sp) & (p2 < sp)
    bottom = a0 < a0.min() + 0.5 * sp
    row_x = bottom & (p2 < sp)                     # along the plane o2 = 0
    row_y = bottom & (p1 < sp)
    l_nb = edge(a[axis_row], a0[axis_row])
    d_nb = edge(o1[row_x], p1[row_x]) + edge(o2[row_y], p2[row_y])   # 2 x the mean of the two radii
    return {"t": t, "np": len(vol), "L": float(np.max(a + h)), "D": d_nb, "L_nb": l_nb,
            "D_planes": 2.0 * float(np.max(b + hb)), "L_ctr": float(np.max(a)), "D_ctr": 2.0 * float(np.max(b)),
            "D_all": 2.0 * float(np.max(r + h)), "epsp": float(np.max(epsp)), "T": float(np.max(temp)), "sp": sp}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outdirs", nargs="+")
    ap.add_argument("--axis", default="z", choices=["x", "y", "z"])
    ap.add_argument("--ref", nargs=2, type=float, default=REFS["DynELA"][:2], metavar=("L", "D"))
    ap.add_argument("--tol-l", type=float, default=0.01)
    ap.add_argument("--tol-d", type=float, default=0.03)
    a = ap.parse_args()
    lref, dref = a.ref
    print(f"reference L_f = {lref} mm, D_f = {dref} mm (DynELA 26.52/11.15, eps_p 1.78, T 582 C; "
          f"Abaqus 26.56/11.16, 1.81, 591 C)")
    print(f"{'run':24s} {'sp':>5s} {'np':>7s} {'L_f':>7s} {'err':>7s} {'D_f':>7s} {'err':>7s} "
          f"{'L0':>7s} {'D0':>6s} {'L_corr':>7s} {'err':>7s} | {'L_ctr':>7s} {'D_ctr':>7s} {'D_pl':>7s} "
          f"{'D_all':>7s} {'epsp':>6s} {'T':>6s}")
    ok = True
    for d in a.outdirs:
        m = measure(d, "xyz".index(a.axis))
        m0 = measure(d, "xyz".index(a.axis), 0)
        lcorr = m["L"] - (m0["L"] - 32.4)
        el, ed, ec = m["L"] / lref - 1.0, m["D"] / dref - 1.0, lcorr / lref - 1.0
        ok = ok and abs(el) <= a.tol_l and abs(ed) <= a.tol_d
        print(f"{os.path.basename(os.path.normpath(d)):24s} {m['sp']:5.3f} {m['np']:7d} {m['L']:7.3f} {el:+7.2%} "
              f"{m['D']:7.3f} {ed:+7.2%} {m0['L']:7.3f} {m0['D']:6.3f} {lcorr:7.3f} {ec:+7.2%} | {m['L_ctr']:7.3f} "
              f"{m['D_ctr']:7.3f} {m['D_planes']:7.3f} {m['D_all']:7.3f} {m['epsp']:6.3f} {m['T']:6.1f}   t = {m['t']:.2f}")
    print(f"bar: |L_f err| <= {a.tol_l:.0%}, |D_f err| <= {a.tol_d:.0%}: {'met' if ok else 'NOT met'}")
    sys.exit(0 if ok else 1)


main()
