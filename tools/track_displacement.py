#!/usr/bin/env python3
"""Displacements of tracked particles from an lsalepm tracks file
(<dir>/<name>_tracks.txt, &output track): per track, the largest
displacement along an axis, when it came, the first peak (the first
maximum after which the displacement falls back by more than --drop of
the largest: the end of the first swing, e.g. a column's first vibration), and the
displacement at the last row.

    track_displacement.py TRACKS [--axis x] [--drop 0.05] [--only 1,2]

Prints one line per track; exit status 1 when the file has no rows.
"""
import argparse
import sys

import numpy as np


def read(path):
    """(column names, rows) of a tracks file."""
    names, rows = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                names = line[1:].split()
            elif line.strip():
                rows.append([float(v) for v in line.split()])
    if names is None or not rows:
        sys.exit("%s: no tracks" % path)
    return names, np.array(rows)


def first_peak(t, u, drop):
    """(time, value) of the first maximum of u (signed towards its largest
    excursion) that u later falls below by drop times the largest, or None."""
    s = np.sign(u[np.argmax(abs(u))]) or 1.0
    v = s * u
    fall = drop * v.max()
    best = 0
    for k in range(len(v)):
        if v[k] > v[best]:
            best = k
        elif v[best] > 0 and v[k] < v[best] - fall:
            return t[best], u[best]
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tracks")
    ap.add_argument("--axis", choices=("x", "y", "z"), default="x")
    ap.add_argument("--drop", type=float, default=0.05)
    ap.add_argument("--only", default="", help="comma-separated track numbers (default: all)")
    a = ap.parse_args()
    names, rows = read(a.tracks)
    t = rows[:, 0]
    ks = [int(n.split("_")[1]) for n in names if n.startswith("id_")]
    if a.only:
        ks = [int(k) for k in a.only.split(",")]
    for k in ks:
        u = rows[:, names.index("%s_%d" % (a.axis, k))]
        ok = np.isfinite(u)
        tt, u = t[ok], u[ok] - u[ok][0]
        i = int(np.argmax(abs(u)))
        fp = first_peak(tt, u, a.drop)
        first = "first peak %+.4g at t = %.4g" % (fp[1], fp[0]) if fp else "no first peak yet"
        print("track %d (id %d): largest %s displacement %+.4g at t = %.4g; %s; at t = %.4g: %+.4g"
              % (k, int(rows[0, names.index("id_%d" % k)]), a.axis, u[i], tt[i], first, tt[-1], u[-1]))


if __name__ == "__main__":
    main()
