#!/usr/bin/python3
"""Writes the STL surfaces of tests/decks/particles_stl.nml (run once; the
files are committed): stl_cube.stl (binary), the cube [0.2,0.6]^3, each
face split along the diagonal from its low (y, z) corner, so rays along x
through points with y = z pass exactly through the split; stl_ell.stl
(binary), an L-shaped prism, the union of [0.7,1.1]x[0.1,0.3]x[0.1,0.7] and
[0.7,0.9]x[0.1,0.7]x[0.1,0.7] (not convex), triangles in no particular
orientation; stl_sphere.stl (ASCII), an icosphere (20 x 4^2 triangles) of
circumradius 0.25 about (0.4, 0.4, 0.4)."""
import struct
import numpy as np


def box_quads(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1),
         (x0, y1, z1)]
    faces = [(0, 3, 7, 4), (1, 2, 6, 5), (0, 1, 5, 4), (3, 2, 6, 7), (0, 1, 2, 3), (4, 5, 6, 7)]
    return [[c[i] for i in f] for f in faces]


def quads_to_tris(quads):
    # split along the diagonal from the first corner (the low one here)
    return [t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])]


def write_binary(path, tris):
    with open(path, "wb") as f:
        f.write(b"binary STL for tests/decks/particles_stl.nml".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<12fH", 0, 0, 0, *[c for v in t for c in v], 0))


def ell_tris():
    # the L in the (y, z) plane... here in (x, y): polygon, extruded along z
    poly = [(0.7, 0.1), (1.1, 0.1), (1.1, 0.3), (0.9, 0.3), (0.9, 0.7), (0.7, 0.7)]
    z0, z1 = 0.1, 0.7
    tris = []
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        tris += [[(a[0], a[1], z0), (b[0], b[1], z0), (b[0], b[1], z1)],
                 [(a[0], a[1], z0), (b[0], b[1], z1), (a[0], a[1], z1)]]
    # caps: the L as two rectangles (0.7..1.1 x 0.1..0.3, 0.7..0.9 x 0.3..0.7), both ends
    for z in (z0, z1):
        for (xa, ya, xb, yb) in ((0.7, 0.1, 1.1, 0.3), (0.7, 0.3, 0.9, 0.7)):
            tris += [[(xa, ya, z), (xb, ya, z), (xb, yb, z)], [(xa, ya, z), (xb, yb, z), (xa, yb, z)]]
    return tris


def icosphere(c, r, levels):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [np.array(p) / np.linalg.norm(p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    tris = [[v[a], v[b], v[d]] for a, b, d in f]
    for _ in range(levels):
        new = []
        for a, b, d in tris:
            ab, bd, da = [(p + q) / np.linalg.norm(p + q) for p, q in ((a, b), (b, d), (d, a))]
            new += [[a, ab, da], [ab, b, bd], [da, bd, d], [ab, bd, da]]
        tris = new
    return [[tuple(np.array(c) + r * p) for p in t] for t in tris]


write_binary("stl_cube.stl", quads_to_tris(box_quads((0.2, 0.2, 0.2), (0.6, 0.6, 0.6))))
write_binary("stl_ell.stl", ell_tris())
with open("stl_sphere.stl", "w") as f:
    f.write("solid sphere\n")
    for t in icosphere((0.4, 0.4, 0.4), 0.25, 2):
        f.write("  facet normal 0 0 0\n    outer loop\n")
        for p in t:
            f.write(f"      vertex {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n")
        f.write("    endloop\n  endfacet\n")
    f.write("endsolid sphere\n")
