#!/usr/bin/python3
"""Checks tests/decks/particles_stl.nml's seeding from STL surfaces, as its
initial frame holds it:

    check_particles_stl.py FRAME.h5 SPHERE.stl

- the binary cube (body 1) seeds exactly the particles of shape = 'box'
  with its corners (body 2): the same positions and volumes (the cube's
  faces are split along y = z: the rays of its 64 particles with y = z run
  along the split, shared by two triangles, and must cross one; without the
  symbolic tie-break 4 of them were lost);
- the binary L-shaped prism (body 3, not convex) exactly the union of its
  two boxes (body 4);
- the ASCII icosphere (body 5) exactly the sub-cell centres (x = 0.025 +
  0.05 k, this 12 x 8 x 8 grid of h = 0.1 at per_cell 2) on the inner
  side of all its 320 face planes (convex), none of them within 1e-9 of a
  plane (so the set does not depend on round-off);
- the cube with scale = 0.5 and offset = (0.5, 0.1, 0.1) (body 6) exactly
  what the box [0.6,0.8] x [0.2,0.4]^2 seeds (body 7);
- the file's two points with scale = 0.5 and offset = (0.1, 0.2, 0.3)
  (body 8) at (0.6, 0.45, 0.5) and (0.2, 0.3, 0.4), their volumes 1e-3 and
  2e-3 times 0.5^3 (to round-off).
Exit status 0 pass, 1 fail.
"""
import sys

import h5py
import numpy as np

f = h5py.File(sys.argv[1], "r")
x = f["particles/x"][()]
vol = f["particles/volume"][()]
body = f["particles/body"][()]
fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


def keyset(b):
    return {(round(p[0], 9), round(p[1], 9), round(p[2], 9), round(v, 15)) for p, v in zip(x[body == b],
                                                                                        vol[body == b])}


for a, b, what in ((1, 2, "binary cube against the box"), (3, 4, "binary L-prism against the union of its boxes"),
                   (6, 7, "the cube scaled by 0.5 and moved by (0.5, 0.1, 0.1) against its box")):
    sa, sb = keyset(a), keyset(b)
    check(len(sa) == (body == a).sum() and sa == sb,
          f"{what}: {(body == a).sum()} and {(body == b).sum()} particles, {len(sa ^ sb)} differ")

# the icosphere: ASCII facets, every third 'vertex' line closes a triangle
verts = [list(map(float, line.split()[1:4])) for line in open(sys.argv[2]) if line.strip().startswith("vertex")]
tri = np.array(verts).reshape(-1, 3, 3)
c = tri.reshape(-1, 3).mean(axis=0)
n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
n *= np.sign(np.einsum("ij,ij->i", n, tri[:, 0] - c))[:, None]      # outward
d = np.einsum("ij,ij->i", n, tri[:, 0])
k = np.arange(24)
g = np.stack(np.meshgrid(0.025 + 0.05 * k, 0.025 + 0.05 * k[:16], 0.025 + 0.05 * k[:16], indexing="ij"),
             axis=-1).reshape(-1, 3)
s = (g @ n.T - d) / np.linalg.norm(n, axis=1)
inside = np.all(s < 0, axis=1)
check(np.abs(s).min() > 1e-9, f"icosphere: no sub-cell centre within 1e-9 of a face plane "
      f"(closest {np.abs(s).min():.3g})")
want = {tuple(np.round(p, 9)) for p in g[inside]}
got = {tuple(np.round(p, 9)) for p in x[body == 5]}
check(want == got, f"icosphere ({len(tri)} triangles): {len(got)} particles, {len(want)} centres inside its "
      f"planes, {len(want ^ got)} differ")
b8 = body == 8
want = {(0.6, 0.45, 0.5): 1.0e-3 / 8, (0.2, 0.3, 0.4): 2.0e-3 / 8}
ok = b8.sum() == 2 and all(any(np.allclose(q, w, rtol=0, atol=1e-15) and abs(v - vw) <= 1e-15 * vw
                               for w, vw in want.items()) for q, v in zip(x[b8], vol[b8]))
check(ok, f"file of points scaled and moved: {b8.sum()} particles at {x[b8].tolist()}, volumes {vol[b8].tolist()}")
print("PASS" if not fails else f"FAIL ({len(fails)})")
sys.exit(1 if fails else 0)
