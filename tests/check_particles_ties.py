#!/usr/bin/python3
"""Checks the hosts of tests/decks/particles_ties.nml's particles in its
initial frame:

    check_particles_ties.py FRAME.h5

The grid is a box of cells h = 0.1 (12 x 8 x 8). A particle at x lies in
the cells [(m-1) h, m h] of each direction with m h >= x >= (m-1) h; where x
is on a face (x = m h) two cells share it, and the host must be the lower
(0-based index ceil(x/h) - 1, the first cell at the grid's low face): the
rule that makes the host independent of where a search started. Checked
for every particle (the bar's 11 pieces and the file's 7 points), with the
natural coordinates then 1 on a shared face (0 at the grid's low face).
Exit status 0 pass, 1 fail.
"""
import sys

import h5py
import numpy as np

f = h5py.File(sys.argv[1], "r")
x = f["particles/x"][()]
cell = f["particles/cell"][()] - 1
body = f["particles/body"][()]
ni, nj = 12, 8
h = 0.1
fails = []
want = np.maximum(np.ceil(x / h - 1e-9) - 1, 0).astype(int)
got = np.stack([cell % ni, (cell // ni) % nj, cell // (ni * nj)], axis=1)
n1, n2 = (body == 1).sum(), (body == 2).sum()
print(f"{n1} particles of the bar, {n2} of the file")
if n1 != 11 or n2 != 7:
    fails.append(f"expected 11 and 7 particles, got {n1} and {n2}")
ties = np.abs(x / h - np.round(x / h)) < 1e-9
print(f"{ties.any(axis=1).sum()} particles on a face, {(ties.sum(axis=1) >= 2).sum()} on an edge or corner")
for q in range(len(x)):
    ok = np.array_equal(got[q], want[q])
    print(("ok    " if ok else "FAIL  ") + f"particle at {x[q]}: host cell {got[q]}, lowest holding {want[q]}")
    if not ok:
        fails.append(f"particle {q}")
print("PASS" if not fails else f"FAIL ({len(fails)})")
sys.exit(1 if fails else 0)
