#!/usr/bin/env python3
"""Nodes fixed by a box (&boundary fixed_lo, fixed_hi) stay at rest and in
place: in every frame of a run, each node whose position in the first frame
lies in the box has velocity exactly 0 and the first frame's position to
the last bit; at least `--count` such nodes, and at least one node outside
the box has moved (the run is not at rest).

usage: check_fixed_nodes.py PREFIX LOX LOY LOZ HIX HIY HIZ --count N
PREFIX: the frames PREFIX_00000.h5, PREFIX_00001.h5, ...
"""
import argparse
import glob
import sys

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("prefix")
    ap.add_argument("box", type=float, nargs=6)
    ap.add_argument("--count", type=int, required=True)
    a = ap.parse_args()
    frames = sorted(glob.glob(a.prefix + "_[0-9][0-9][0-9][0-9][0-9].h5"))
    if len(frames) < 2:
        sys.exit(f"FAIL: fewer than two frames {a.prefix}_NNNNN.h5")
    lo, hi = np.array(a.box[:3]), np.array(a.box[3:])
    with h5py.File(frames[0], "r") as f:
        x0 = f["x"][...].reshape(-1, 3)
    inside = np.all((x0 >= lo) & (x0 <= hi), axis=1)
    n = int(inside.sum())
    if n != a.count:
        sys.exit(f"FAIL: {n} nodes in the box, expected {a.count}")
    moved = 0.0
    for name in frames[1:]:
        with h5py.File(name, "r") as f:
            x = f["x"][...].reshape(-1, 3)
            u = f["velocity"][...].reshape(-1, 3)
        if np.any(u[inside] != 0.0):
            sys.exit(f"FAIL: {name}: a fixed node moves, |u| up to {np.abs(u[inside]).max():.3e}")
        if np.any(x[inside] != x0[inside]):
            sys.exit(f"FAIL: {name}: a fixed node left its place by {np.abs(x[inside] - x0[inside]).max():.3e}")
        moved = max(moved, float(np.abs(x[~inside] - x0[~inside]).max()))
    if not moved > 0.0:
        sys.exit("FAIL: no node moved: the run is at rest")
    print(f"ok: {n} fixed nodes at rest and in place in {len(frames) - 1} frames (other nodes moved up to {moved:.3e})")


if __name__ == "__main__":
    main()
