#!/usr/bin/env python3
"""Fragments of a ring (paper Sect. 7.6, Table 6): counts and measures them
from the particle output.

    fragments.py FRAME0 FRAME [FRAME ...] [--center X Y] [--bond 1.1]
                 [--main 0.02] [--quarter]

FRAME0 is the first frame (t = 0, the particles' initial places). Two
particles are bonded when they were within BOND times the initial particle
spacing of each other at t = 0 (the spacing: the median nearest-neighbour
distance; the default 1.1 bonds lattice neighbours along the axes only,
so that a crack one particle wide separates, however it runs across the
lattice) and neither has failed; a fragment is a connected set of bonded
particles (failed particles are the cracks). Particles that have left the
grid through an open face (missing from a frame) belong to no fragment;
the "left" column counts them. In the plane through CENTER
(default 0, 0) each fragment is measured along its midline:

- width: its angular extent times its mean radius;
- thickness: the mean, over angular slices one spacing wide, of the radial
  extent of the slice plus one spacing (a particle stands for a spacing).

A main fragment holds at least MAIN of the particles. With --quarter the
scene is a quarter model with symmetry planes x = 0 and y = 0: a fragment
that reaches a symmetry plane (within one spacing) is half of a fragment
and its width is doubled (flagged "sym").

For each FRAME: time, failed particles, fragments, main fragments; for the
last FRAME the main fragments' list and the mean width/thickness. Also the
first FRAME with two or more main fragments (the first through-crack, to
the frame spacing). Read with h5py (run with /usr/bin/python3).
"""
import argparse
import sys

import h5py
import numpy as np


def load(path, ids0=None):
    """Time, positions and failure flags in id order. With ids0 (the first
    frame's ids), on those ids: a particle that has left the grid through
    an open face (not in the frame) gets NaN position, and gone True."""
    with h5py.File(path, "r") as f:
        if "particles/x" in f and "particles/id" not in f:
            sys.exit(f"{path}: no particles/id (the deck's &output particle_fields must include 'id')")
        ids = f["particles/id"][()]
        order = np.argsort(ids)
        x = f["particles/x"][()][order]
        if "particles/failed" not in f and ids0 is None:
            print(f"{path}: no particles/failed (not in &output particle_fields?): no particle counts as failed",
                  file=sys.stderr)
        failed = f["particles/failed"][()][order] > 0.5 if "particles/failed" in f else np.zeros(len(x), bool)
        t = float(f["time"][()])
    if ids0 is None:
        return t, x, failed, ids[order]
    at = np.searchsorted(ids0, ids[order])
    if np.any(at >= len(ids0)) or np.any(ids0[np.minimum(at, len(ids0) - 1)] != ids[order]):
        sys.exit(f"{path}: particle ids that the first frame does not have")
    xa = np.full((len(ids0), 3), np.nan)
    fa = np.zeros(len(ids0), bool)
    gone = np.ones(len(ids0), bool)
    xa[at], fa[at], gone[at] = x, failed, False
    return t, xa, fa, gone


def bonds(x0, factor):
    """Pairs (i, j), i < j, within factor x spacing at t = 0, and the spacing."""
    from scipy.spatial import cKDTree
    tree = cKDTree(x0)
    d, _ = tree.query(x0, k=2)
    spacing = float(np.median(d[:, 1]))
    pairs = tree.query_pairs(factor * spacing, output_type="ndarray")
    return pairs, spacing


def components(n, pairs, alive):
    """Labels of the connected components of the alive particles (-1 dead)."""
    parent = np.arange(n)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    keep = alive[pairs[:, 0]] & alive[pairs[:, 1]]
    for i, j in pairs[keep]:
        ri, rj = find(i), find(j)
        if ri != rj:
            parent[max(ri, rj)] = min(ri, rj)
    labels = np.array([find(i) for i in range(n)])
    labels[~alive] = -1
    return labels


def measure(x, spacing, center, quarter):
    """Width, thickness and the symmetry flag of one fragment's particles."""
    r = np.hypot(x[:, 0] - center[0], x[:, 1] - center[1])
    th = np.arctan2(x[:, 1] - center[1], x[:, 0] - center[0])
    if not quarter and th.max() - th.min() > np.pi:
        th = np.mod(th, 2.0 * np.pi)   # a fragment across the -x axis
    rm = float(r.mean())
    dth = spacing / rm
    width = (th.max() - th.min()) * rm + spacing
    slices = np.floor((th - th.min()) / dth).astype(int)
    thick = [r[slices == s].max() - r[slices == s].min() + spacing for s in np.unique(slices)]
    sym = quarter and (x[:, 0].min() - center[0] < spacing or x[:, 1].min() - center[1] < spacing)
    if sym:
        width *= 2.0
    return width, float(np.mean(thick)), sym


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("frames", nargs="+")
    ap.add_argument("--center", nargs=2, type=float, default=[0.0, 0.0])
    ap.add_argument("--bond", type=float, default=1.1)
    ap.add_argument("--main", type=float, default=0.02)
    ap.add_argument("--quarter", action="store_true")
    a = ap.parse_args()
    if len(a.frames) < 2:
        sys.exit("give the first frame and at least one more")
    _, x0, _, ids0 = load(a.frames[0])
    pairs, spacing = bonds(x0, a.bond)
    n = len(x0)
    print(f"{n} particles, spacing {spacing:.4g}, {len(pairs)} bonds (within {a.bond} spacings at t = 0)")
    print(f"{'time':>12s} {'failed':>7s} {'left':>5s} {'fragments':>9s} {'main':>5s}")
    first_crack = None
    for path in a.frames[1:]:
        t, x, failed, gone = load(path, ids0)
        labels = components(n, pairs, ~failed & ~gone)
        ids, sizes = np.unique(labels[labels >= 0], return_counts=True)
        main_ids = ids[sizes >= a.main * n]
        print(f"{t:12.5g} {int(failed.sum()):7d} {int(gone.sum()):5d} {len(ids):9d} {len(main_ids):5d}")
        if first_crack is None and len(main_ids) >= 2:
            first_crack = t
    print(f"first frame with two or more main fragments (first through-crack): "
          f"{'none' if first_crack is None else f'{first_crack:.5g}'}")
    rows = []
    for c in main_ids:
        w, h, sym = measure(x[labels == c], spacing, a.center, a.quarter)
        rows.append((w, h, sym, int((labels == c).sum())))
    rows.sort(key=lambda r: -r[3])
    print(f"main fragments at t = {t:.5g} (at least {a.main:g} of the particles):")
    print(f"{'particles':>9s} {'width':>9s} {'thickness':>9s}")
    for w, h, sym, m in rows:
        print(f"{m:9d} {w:9.4g} {h:9.4g}{'  sym (width doubled)' if sym else ''}")
    if rows:
        print(f"mean width/thickness of the main fragments: {np.mean([r[0] for r in rows]):.4g} / "
              f"{np.mean([r[1] for r in rows]):.4g}")


if __name__ == "__main__":
    main()
