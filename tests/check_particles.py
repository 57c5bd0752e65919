#!/usr/bin/python3
"""Checks the particles a deck seeded, as written in a frame (tests/decks/
particles_sedov.nml, its initial frame):

    check_particles.py FRAME.h5

- counts per body: the steel box [0.72,1.08]x[0.72,0.96]x[0,0.24] covers
  3 x 2 x 2 cells of h = 0.12 at per_cell 2: exactly 96 particles, volume
  0.36*0.24*0.24 to round-off (1e-14 relative: 96 terms), mass 7.85 x that;
  the three points of particles_points.txt at their exact positions, each
  with its host cell's volume / 2^3;
- mass = density x volume for every particle (one rounding: 2 eps);
- the rotating sphere (body 7): v = (0.1,0,0) + 2 z x (x - c), c = (0.6,0.3,0.6),
  to 4 eps |v|; the others at rest; the cylinder's stress -0.5 I exactly;
- every particle lies in its host cell (this box grid: within its bounds;
  natural coordinates are tested on a distorted grid by test_particles);
- order: by material, then by host cell; ids a permutation of 1..np.
Exit status 0 pass, 1 fail.
"""
import sys

import h5py
import numpy as np

f = h5py.File(sys.argv[1], "r")
p = {k: f["particles/" + k][()] for k in f["particles"]}
xg = f["x"][()]                          # (nk+1, nj+1, ni+1, 3)
eps = np.finfo(float).eps
fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


body, vol, m, rho, x, v = p["body"], p["volume"], p["mass"], p["density"], p["x"], p["velocity"]
box = body == 1
check(box.sum() == 96, f"steel box: {box.sum()} particles, expected 96 (12 cells x 2^3)")
vb = 0.36 * 0.24 * 0.24
check(abs(vol[box].sum() / vb - 1) < 1e-14, f"steel box volume {vol[box].sum():.17g} / {vb} - 1 < 1e-14")
check(abs(m[box].sum() / (7.85 * vb) - 1) < 1e-14, "steel box mass = 7.85 x volume")
check(np.all(np.abs(m - rho * vol) <= 2 * eps * m), "mass = density x volume (2 eps)")
pts = body == 4
want = np.array([[0.95, 0.25, 1.05], [1.0, 1.0, 1.0], [0.06, 1.14, 0.5]])
got = x[pts][np.argsort(p["id"][pts])]
check(pts.sum() == 3 and np.array_equal(got, want), "file points at their exact positions")
check(np.allclose(vol[pts], 0.12 ** 3 / 8, rtol=1e-14, atol=0), "file points: volume = host cell / 2^3")
sph = body == 7
c = np.array([0.6, 0.3, 0.6])
vw = np.array([0.1, 0, 0]) + 2.0 * np.stack([-(x[sph, 1] - c[1]), x[sph, 0] - c[0], 0 * x[sph, 0]], axis=1)
err = np.abs(v[sph] - vw).max()
check(sph.sum() > 0 and err <= 4 * eps * np.abs(vw).max(), f"rotating sphere: max |v - v_rigid| = {err:.2e}")
check(np.all(v[~sph] == 0), "the other bodies at rest")
cyl = body == 3
check(np.all(p["stress"][cyl] == np.array([-0.5, 0, 0, -0.5, 0, -0.5])), "cylinder stress -0.5 I")
# host cell (i fastest, 1-based) and xi -> trilinear map of the cell's nodes
nk, nj, ni = (s - 1 for s in xg.shape[:3])
cell = p["cell"] - 1
i, j, k = cell % ni, (cell // ni) % nj, cell // (ni * nj)
# on this box grid a particle's host cell holds it: its fraction of the cell is in [0,1]
lo = xg[k, j, i]
hi = xg[k + 1, j + 1, i + 1]
frac = (x - lo) / (hi - lo)
check(np.all((frac >= -1e-14) & (frac <= 1 + 1e-14)), "every particle lies in its host cell")
mat = p["material"]
order_ok = np.all(np.diff(mat) >= 0) and all(np.all(np.diff(cell[mat == s]) >= 0) for s in np.unique(mat))
check(order_ok, "sorted by material, then host cell")
check(np.array_equal(np.sort(p["id"]), np.arange(1, len(p["id"]) + 1)), "ids are a permutation of 1..np")
print("FAIL" if fails else "PASS")
sys.exit(1 if fails else 0)
