#!/usr/bin/env python3
"""Fragments of particle bodies from the particle output: counts them,
writes each one's mass, centre of mass, velocity and size (--csv), and
measures the fragments of a ring (paper Sect. 7.6, Table 6).

    fragments.py FRAME0 FRAME [FRAME ...] [--center X Y] [--bond 1.1]
                 [--gaps G] [--main 0.02] [--quarter] [--body 1,2] [--csv FILE]
                 [--no-ring]

FRAME0 is the first frame (t = 0, the particles' initial places). Two
particles are bonded when they were within BOND times the initial particle
spacing of each other at t = 0 (the spacing: the median nearest-neighbour
distance; the default 1.1 bonds lattice neighbours along the axes only,
so that a crack one particle wide separates, however it runs across the
lattice), belong to the same body and neither has failed; a fragment is a
connected set of bonded particles (failed particles are the cracks).
With --gaps G a fragment is instead a connected set of particles, failed
or not, within G initial spacings of each other in that frame (and of the
same body): the pieces the particles' own gaps separate, as fragments
recovered after a test are whole pieces, whatever damage they carry.
--body takes the bodies to look at (the frames' particles/body, e.g. 1 or
1,3; default all), the other particles are left out as if absent. Particles that have left the
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
last FRAME the main fragments' list and the mean width/thickness (the ring
report; --no-ring leaves it out). Also the first FRAME with two or more
main fragments (the first through-crack, to the frame spacing).

--csv FILE writes every fragment (any size, any body shape) of every FRAME
after FRAME0, one row each, the largest by mass first within a frame:
time, fragment (1, 2, ... in that order), body, particles, mass, centre of
mass cx cy cz, mass-averaged velocity vx vy vz, bounding box extents
box_x box_y box_z and the extents along the principal axes of its mass
distribution (the eigenvectors of the mass-weighted covariance of the
positions about the centre of mass) axis_1 >= axis_2 >= axis_3, each the
span of the particle centres plus one spacing (a particle stands for a
spacing: a lone particle is a cube one spacing wide). The frames must
hold particles/mass, velocity and body (lsalepm frames do). Read with h5py
(run with /usr/bin/python3).
"""
import csv
import argparse
import sys

import h5py
import numpy as np


def load(path, ids0=None, extra=False):
    """Time, positions and failure flags in id order. With ids0 (the first
    frame's ids), on those ids: a particle that has left the grid through
    an open face (not in the frame) gets NaN position, and gone True.
    With extra, also a dict of the frames' mass, velocity and body on the
    same particles (None where the frame has none; NaN / -1 for the gone)."""
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
        more = {k: (f["particles/" + k][()][order] if "particles/" + k in f else None)
                for k in ("mass", "velocity", "body")}
    if ids0 is None:
        return (t, x, failed, ids[order]) + ((more,) if extra else ())
    at = np.searchsorted(ids0, ids[order])
    if np.any(at >= len(ids0)) or np.any(ids0[np.minimum(at, len(ids0) - 1)] != ids[order]):
        sys.exit(f"{path}: particle ids that the first frame does not have")
    xa = np.full((len(ids0), 3), np.nan)
    fa = np.zeros(len(ids0), bool)
    gone = np.ones(len(ids0), bool)
    xa[at], fa[at], gone[at] = x, failed, False
    if not extra:
        return t, xa, fa, gone
    for k, v in more.items():
        if v is not None:
            full = np.full((len(ids0),) + v.shape[1:], -1 if k == "body" else np.nan,
                           dtype=v.dtype if k == "body" else float)
            full[at] = v
            more[k] = full
    return t, xa, fa, gone, more


def pairs_within(x, dist, body=None, present=None):
    """Pairs (i, j), i < j, of particles (the present ones, if given)
    within dist of each other at positions x, and of the same body if
    given."""
    from scipy.spatial import cKDTree
    idx = np.arange(len(x)) if present is None else np.nonzero(present)[0]
    pairs = idx[cKDTree(x[idx]).query_pairs(dist, output_type="ndarray")].reshape(-1, 2)
    if body is not None and len(pairs):
        pairs = pairs[body[pairs[:, 0]] == body[pairs[:, 1]]]
    return pairs


def bonds(x0, factor, body=None):
    """Pairs (i, j), i < j, within factor x spacing at t = 0 (and of the
    same body, if given), and the spacing."""
    from scipy.spatial import cKDTree
    d, _ = cKDTree(x0).query(x0, k=2)
    spacing = float(np.median(d[:, 1]))
    return pairs_within(x0, factor * spacing, body), spacing


def fragment_rows(t, x, more, labels, spacing):
    """One dict per fragment (labels >= 0) for the CSV, the heaviest first."""
    rows = []
    for c in np.unique(labels[labels >= 0]):
        sel = labels == c
        m, xs, vs = more["mass"][sel], x[sel], more["velocity"][sel]
        mt = float(m.sum())
        com = (m[:, None] * xs).sum(axis=0) / mt
        vel = (m[:, None] * vs).sum(axis=0) / mt
        box = xs.max(axis=0) - xs.min(axis=0) + spacing
        d = xs - com
        cov = (m[:, None, None] * d[:, :, None] * d[:, None, :]).sum(axis=0) / mt
        _, axes = np.linalg.eigh(cov)
        proj = d @ axes
        ext = np.sort(proj.max(axis=0) - proj.min(axis=0))[::-1] + spacing
        bodies = np.unique(more["body"][sel])
        rows.append({"time": t, "body": int(bodies[0]) if len(bodies) == 1 else -1,
                     "particles": int(sel.sum()), "mass": mt,
                     "cx": com[0], "cy": com[1], "cz": com[2], "vx": vel[0], "vy": vel[1], "vz": vel[2],
                     "box_x": box[0], "box_y": box[1], "box_z": box[2],
                     "axis_1": ext[0], "axis_2": ext[1], "axis_3": ext[2]})
    rows.sort(key=lambda r: -r["mass"])
    for k, r in enumerate(rows):
        r["fragment"] = k + 1
    return rows


CSV_COLUMNS = ["time", "fragment", "body", "particles", "mass", "cx", "cy", "cz", "vx", "vy", "vz",
               "box_x", "box_y", "box_z", "axis_1", "axis_2", "axis_3"]


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
    ap.add_argument("--gaps", type=float, metavar="G",
                    help="fragments by the gaps in each frame: particles within G spacings, failed or not")
    ap.add_argument("--main", type=float, default=0.02)
    ap.add_argument("--quarter", action="store_true")
    ap.add_argument("--body", help="the bodies to look at, e.g. 1 or 1,3 (default all)")
    ap.add_argument("--csv", metavar="FILE", help="write every fragment of every FRAME to FILE")
    ap.add_argument("--no-ring", action="store_true", help="leave out the ring's width/thickness report")
    a = ap.parse_args()
    if len(a.frames) < 2:
        sys.exit("give the first frame and at least one more")
    _, x0, _, ids0, more0 = load(a.frames[0], extra=True)
    body0 = more0["body"]
    chosen = np.ones(len(x0), bool)
    if a.body:
        try:
            want = [int(b) for b in a.body.split(",")]
        except ValueError:
            sys.exit(f"--body takes body numbers like 1 or 1,3, got {a.body!r}")
        if body0 is None:
            sys.exit(f"{a.frames[0]}: no particles/body to choose bodies from")
        chosen = np.isin(body0, want)
        if not chosen.any():
            sys.exit(f"no particle of body {a.body}; the bodies are {sorted(set(body0.tolist()))}")
    pairs, spacing = bonds(x0, a.bond, body0)
    n = len(x0)
    print(f"{n} particles, spacing {spacing:.4g}, {len(pairs)} bonds (within {a.bond} spacings at t = 0)"
          + (f"; bodies {a.body}: {int(chosen.sum())} particles" if a.body else ""))
    print(f"{'time':>12s} {'failed':>7s} {'left':>5s} {'fragments':>9s} {'main':>5s}")
    first_crack = None
    table = []
    for path in a.frames[1:]:
        t, x, failed, gone, more = load(path, ids0, extra=True)
        if a.gaps is None:
            labels = components(n, pairs, ~failed & ~gone & chosen)
        else:
            labels = components(n, pairs_within(x, a.gaps * spacing, body0, ~gone & chosen), ~gone & chosen)
        if a.csv:
            missing = [k for k in ("mass", "velocity", "body") if more[k] is None]
            if missing:
                sys.exit(f"{path}: no particles/{', particles/'.join(missing)} for --csv")
            table += fragment_rows(t, x, more, labels, spacing)
        ids, sizes = np.unique(labels[labels >= 0], return_counts=True)
        main_ids = ids[sizes >= a.main * n]
        print(f"{t:12.5g} {int(failed.sum()):7d} {int(gone.sum()):5d} {len(ids):9d} {len(main_ids):5d}")
        if first_crack is None and len(main_ids) >= 2:
            first_crack = t
    print(f"first frame with two or more main fragments (first through-crack): "
          f"{'none' if first_crack is None else f'{first_crack:.5g}'}")
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
            w.writeheader()
            for r in table:
                w.writerow({k: (repr(float(v)) if isinstance(v, (float, np.floating)) else v)
                            for k, v in r.items()})
        print(f"{len(table)} fragment rows written to {a.csv}")
    if a.no_ring:
        return
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
