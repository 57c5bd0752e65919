#!/usr/bin/python3
"""Checks the block cuts a decomposed run logged against the ones its
particles call for:

    check_block_cuts.py FRAME0.h5 WEIGHT LOG...

FRAME0.h5 is the one-process run's initial frame (its particles all seeded
by shape groups), WEIGHT the deck's &run blocks_particle_weight, each LOG a
decomposed run's log with its line "run: P MPI ranks, blocks a x b x c
(...), cut at i = ... j = ... (...)". In each direction d cut into p blocks
the work of a plane of cells normal to d is its cells plus WEIGHT times the
particles hosted in it; the cut between blocks b and b + 1 is the plane
boundary whose prefix of work is nearest to (b + 1)/p of the whole (the
lower on a tie), each block at least as thick as its ghost layers (the
log's "ghost layers g"; parallel_cuts). The
logged cuts must be these, and differ from the cells-only cuts (equal
cells within one) somewhere, or the check would not see the particles.
Exit status 0 pass, 1 fail.
"""
import re
import sys

import h5py
import numpy as np

frame, weight, logs = sys.argv[1], float(sys.argv[2]), sys.argv[3:]
f = h5py.File(frame, "r")
gn = np.array(f["x"].shape[2::-1]) - 1          # (nk+1, nj+1, ni+1, 3) -> ni, nj, nk
cell = f["particles/cell"][()] - 1
ijk = [cell % gn[0], (cell // gn[0]) % gn[1], cell // (gn[0] * gn[1])]
fails = []


def cuts(w, p, m):
    prefix = np.concatenate([[0.0], np.cumsum(w)])
    c, e = [0], 0
    for b in range(1, p):
        target = prefix[-1] * b / p
        while e < len(w) and prefix[e + 1] <= target:
            e += 1
        cb = e + 1 if e < len(w) and prefix[e + 1] - target < target - prefix[e] else e
        c.append(min(max(cb, c[-1] + m), len(w) - (p - b) * m))
    return c[1:]


for log in logs:
    line = next(l for l in open(log) if l.startswith("run: ") and " MPI ranks, blocks " in l)
    dims = [int(v) for v in re.search(r"blocks (\d+) x (\d+) x (\d+)", line).groups()]
    m = max(int(re.search(r"ghost layers (\d+)", line).group(1)), 1)
    differ = False
    for d, axis in enumerate("ijk"):
        if dims[d] == 1:
            continue
        planes = np.bincount(ijk[d], minlength=gn[d])
        cells = np.prod(gn) / gn[d]
        want = cuts(cells + weight * planes, dims[d], m)
        got = [int(v) for v in re.search(axis + r" =((?: \d+)+)", line).group(1).split()]
        even = [b * (gn[d] // dims[d]) + min(b, gn[d] % dims[d]) for b in range(1, dims[d])]
        differ = differ or want != even
        ok = got == want
        print(("ok    " if ok else "FAIL  ") + f"{log}: cuts in {axis} {got}, from the particles {want} "
              f"(equal cells: {even})")
        if not ok:
            fails.append(log)
    if not differ:
        fails.append(log)
        print(f"FAIL  {log}: the particles' cuts are the cells' alone: nothing checked")
print("PASS" if not fails else f"FAIL ({len(fails)})")
sys.exit(1 if fails else 0)
