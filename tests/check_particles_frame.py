#!/usr/bin/python3
"""Checks what tests/decks/particles_frame.nml seeded, as its initial frame
holds it:

    check_particles_frame.py FRAME.h5

- body 1, a column [0.2,0.4]^2 x [0,0.8] and a slab [0.2,1.0] x [0.2,0.6] x
  [0.4,0.6] at per_cell 2 on cells of h = 0.1: their union once, 704
  particles (256 + 512 - the 64 of the joint [0.2,0.4]^2 x [0.4,0.6]), each at
  a sub-cell centre (0.025 + 0.05 k in every direction), no two at one
  place, volume 0.032 + 0.064 - 0.008 = 0.088 to round-off (1e-13 relative);
- body 2, two bars (area 1e-4) along the segments the deck gives: at n =
  nint(2 L/h) equal pieces' midpoints (14 and 15 particles), each of volume
  area L/n, so each bar's volume is area L to round-off; every particle of
  body 2 on one of the two segments at parameter (i - 1/2)/n;
- every particle in its host cell's bounds (this box grid).
Exit status 0 pass, 1 fail.
"""
import sys

import h5py
import numpy as np

f = h5py.File(sys.argv[1], "r")
p = {k: f["particles/" + k][()] for k in f["particles"]}
fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


body, vol, x = p["body"], p["volume"], p["x"]
h = 0.1
b1 = body == 1
check(b1.sum() == 704, f"column and slab: {b1.sum()} particles, expected 704 (their union once)")
v1 = vol[b1].sum()
check(abs(v1 - 0.088) <= 1e-13 * 0.088, f"column and slab: volume {v1:.16g}, expected 0.088")
k = (x[b1] - 0.025) / 0.05
check(np.abs(k - np.round(k)).max() < 1e-9, "column and slab: every particle at a sub-cell centre")
keys = {tuple(q) for q in np.round(k).astype(int)}
check(len(keys) == b1.sum(), f"column and slab: {len(keys)} distinct places for {b1.sum()} particles")
inside = [((0.2, 0.2, 0.0), (0.4, 0.4, 0.8)), ((0.2, 0.2, 0.4), (1.0, 0.6, 0.6))]
ok = all(any(np.all(q > lo) and np.all(q < hi) for lo, hi in inside) for q in x[b1])
check(ok, "column and slab: every particle inside the column or the slab")

area = 1.0e-4
bars = [(np.array([0.3, 0.3, 0.05]), np.array([0.3, 0.3, 0.75])),
        (np.array([0.25, 0.25, 0.45]), np.array([0.95, 0.55, 0.55]))]
b2 = np.flatnonzero(body == 2)
used = np.zeros(len(b2), bool)
for m, (a, b) in enumerate(bars):
    length = np.linalg.norm(b - a)
    n = max(1, int(np.floor(2 * length / h + 0.5)))
    want = a + ((np.arange(n) + 0.5) / n)[:, None] * (b - a)
    hit = []
    for w in want:
        d = np.linalg.norm(x[b2] - w, axis=1)
        j = int(np.argmin(d))
        hit.append(j if d[j] <= 1e-12 else -1)
    found = [j for j in hit if j >= 0]
    check(len(found) == n, f"bar {m + 1}: {len(found)} of its {n} particles at the pieces' midpoints")
    used[found] = True
    vb = vol[b2[found]].sum()
    check(abs(vb - area * length) <= 1e-13 * area * length, f"bar {m + 1}: volume {vb:.16g}, area L = "
          f"{area * length:.16g}")
check(used.all(), f"bars: {used.sum()} of body 2's {len(b2)} particles on the two segments")

xg = f["x"][()]                      # (nk+1, nj+1, ni+1, 3)
cell = p["cell"] - 1
ni, nj = xg.shape[2] - 1, xg.shape[1] - 1
ci, cj, ck = cell % ni, (cell // ni) % nj, cell // (ni * nj)
lo = np.stack([xg[0, 0, ci, 0], xg[0, cj, 0, 1], xg[ck, 0, 0, 2]], axis=1)
hi = np.stack([xg[0, 0, ci + 1, 0], xg[0, cj + 1, 0, 1], xg[ck + 1, 0, 0, 2]], axis=1)
check(bool(np.all(x >= lo - 1e-12) and np.all(x <= hi + 1e-12)), "every particle in its host cell")
print("PASS" if not fails else f"FAIL ({len(fails)})")
sys.exit(1 if fails else 0)
