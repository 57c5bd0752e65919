#!/usr/bin/env python3
"""The Taylor bar (PARTICLES.md §2.7 anchor 1, input/taylor_bar.nml): final
length, mushroom (foot) diameter, largest plastic strain and temperature
from the particles of the last frame of a run.

    taylor_measure.py OUTDIR [OUTDIR ...] [--axis z] [--ref L D] [--tol-l 0.01] [--tol-d 0.03]

Each OUTDIR holds the HDF5 frames of one run of a quarter model whose bar
stands on the plane axis = 0 (the rigid wall) with its axis along the
grid's `axis` through x = y = 0 (or the two other coordinates for another
axis). Read from the last frame (sorted by name):

  L_f = max over particles of (a + h_p), a the coordinate along the axis,
  D_f = 2 max over particles of (r + h_p), r the distance from the axis,

h_p = V_p^(1/3)/2 the half-width of the particle's cube of its current
volume: particles are the centres of their volumes, so the material reaches
about half a particle beyond the outermost centre. That half-width is exact
for the top (hardly strained) end and an estimate for the foot, whose rim
particles are flattened and stretched around the hoop; the centre-only
figures (h_p = 0) are printed too, so that the spread between the two bounds
the surface reconstruction's part of the error (it shrinks with the
particle spacing; the resolution study extrapolates it). Also printed: the
largest 'plastic_strain' and 'temperature' of the frame (the model's
fields), the time and the number of particles, and with --ref the relative
errors against the reference (default DynELA: L_f 26.52 mm, D_f 11.15 mm);
the exit status is 1 if any run misses --tol-l or --tol-d (relative), 0
otherwise. Run with /usr/bin/python3 (h5py, numpy).
"""
import argparse
import glob
import os
import sys

import h5py
import numpy as np

REFS = {"DynELA": (26.52, 11.15, 1.78, 582.0), "Abaqus": (26.56, 11.16, 1.81, 591.0)}


def measure(outdir, axis):
    """(t, np, L_f, D_f, L_centres, D_centres, eps_p max, T max) of the last frame."""
    frames = sorted(glob.glob(os.path.join(outdir, "*.h5")))
    if not frames:
        sys.exit(f"{outdir}: no HDF5 frames")
    with h5py.File(frames[-1], "r") as f:
        x = f["particles/x"][()]
        vol = f["particles/volume"][()]
        t = float(f["time"][()])
        epsp = f["particles/plastic_strain"][()] if "particles/plastic_strain" in f else np.zeros(len(vol))
        temp = f["particles/temperature"][()] if "particles/temperature" in f else np.zeros(len(vol))
    if x.shape[0] != len(vol):
        x = x.T
    a = x[:, axis]
    others = [d for d in range(3) if d != axis]
    r = np.hypot(x[:, others[0]], x[:, others[1]])
    h = 0.5 * np.cbrt(vol)
    return (t, len(vol), float(np.max(a + h)), 2.0 * float(np.max(r + h)), float(np.max(a)),
            2.0 * float(np.max(r)), float(np.max(epsp)), float(np.max(temp)))


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
    print(f"{'run':32s} {'t':>6s} {'np':>7s} {'L_f':>7s} {'err':>7s} {'D_f':>7s} {'err':>7s} "
          f"{'L_ctr':>7s} {'D_ctr':>7s} {'epsp':>6s} {'T':>6s}")
    ok = True
    for d in a.outdirs:
        t, n, lf, df, lc, dc, ep, tm = measure(d, "xyz".index(a.axis))
        el, ed = lf / lref - 1.0, df / dref - 1.0
        ok = ok and abs(el) <= a.tol_l and abs(ed) <= a.tol_d
        print(f"{os.path.basename(os.path.normpath(d)):32s} {t:6.2f} {n:7d} {lf:7.3f} {el:+7.2%} {df:7.3f} "
              f"{ed:+7.2%} {lc:7.3f} {dc:7.3f} {ep:6.3f} {tm:6.1f}")
    print(f"bar: |L_f err| <= {a.tol_l:.0%}, |D_f err| <= {a.tol_d:.0%}: {'met' if ok else 'NOT met'}")
    sys.exit(0 if ok else 1)


main()
