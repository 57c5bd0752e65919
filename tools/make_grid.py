#!/usr/bin/python3
"""Write a grid file for `&grid file = '...'`: an HDF5 file whose dataset `x`
holds the node coordinates with the shape (nk+1, nj+1, ni+1, 3) as h5py sees
it (the Fortran array x(3, 0:ni, 0:nj, 0:nk), the `x` of the code's own
frames). The deck gives the same ni, nj, nk.

    make_grid.py box      --ni 10 --nj 10 --nk 1 [--xmin 0 0 0] [--xmax 1 1 1] --out box.h5
    make_grid.py perturb  --ni 10 --nj 10 --nk 10 --fraction 0.2 [--seed 1] [--xmin ..] [--xmax ..] --out p.h5
    make_grid.py saltzman [--ni 100] [--nj 10] [--dz 0.01] --out saltzman.h5

box       a uniform box grid (the grid `&grid` builds without a file).
perturb   the box grid with every node moved by a uniform random amount of
          up to `fraction` (< 0.5) of the cell size along each direction in
          which it may move: interior nodes in all three, nodes on a face of
          the block only within the face, nodes on an edge only along the
          edge, corners not at all (so the block keeps its planar faces and
          the boundary conditions hold). Seeded: the same seed, the same grid.
saltzman  the skewed grid of the Saltzman piston problem (Dukowicz and Meltz
          1992, as used by Caramana, Shashkov and Whalen 1998): ni x nj cells
          on [0,1] x [0,0.1] with x = x0 + (0.1 - y0) sin(pi x0), y = y0, x0 and
          y0 the uniform grid's coordinates (100 x 10 cells by default), one
          cell of thickness dz in z. The faces x = 0, x = 1, y = 0 and y = 0.1
          stay planar.

The file is written to a temporary name and renamed. Exit status 0 written,
2 bad arguments.
"""
import argparse
import math
import os
import sys

import debian_python  # tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("h5py", "numpy")
import h5py  # noqa: E402
import numpy as np  # noqa: E402


def box_nodes(ni, nj, nk, xmin, xmax):
    """Node coordinates (nk+1, nj+1, ni+1, 3) of a uniform box grid; the far
    faces exactly at xmax (as the code's own box grid)."""
    axes = []
    for n, lo, hi in zip((ni, nj, nk), xmin, xmax):
        h = (hi - lo) / n
        a = lo + h * np.arange(n + 1, dtype=float)
        a[-1] = hi
        axes.append(a)
    z, y, x = np.meshgrid(axes[2], axes[1], axes[0], indexing="ij")
    return np.stack([x, y, z], axis=-1)


def perturb(nodes, fraction, seed):
    """Moves every node by up to `fraction` of the cell size along each
    logical direction in which it is not on the block's boundary."""
    nk, nj, ni = (s - 1 for s in nodes.shape[:3])
    rng = np.random.default_rng(seed)
    out = nodes.copy()
    # cell sizes along x, y, z (uniform box)
    h = [(nodes[0, 0, -1, 0] - nodes[0, 0, 0, 0]) / ni,
         (nodes[0, -1, 0, 1] - nodes[0, 0, 0, 1]) / nj,
         (nodes[-1, 0, 0, 2] - nodes[0, 0, 0, 2]) / nk]
    k, j, i = np.meshgrid(np.arange(nk + 1), np.arange(nj + 1), np.arange(ni + 1), indexing="ij")
    for d, (idx, n) in enumerate(((i, ni), (j, nj), (k, nk))):
        free = (idx > 0) & (idx < n)
        move = fraction * h[d] * rng.uniform(-1.0, 1.0, size=free.shape)
        out[..., d] += np.where(free, move, 0.0)
    return out


def saltzman(ni, nj, dz):
    """The Saltzman grid on [0,1] x [0,0.1] x [0,dz]."""
    nodes = box_nodes(ni, nj, 1, (0.0, 0.0, 0.0), (1.0, 0.1, dz))
    x0 = nodes[..., 0].copy()
    y0 = nodes[..., 1]
    nodes[..., 0] = x0 + (0.1 - y0) * np.sin(math.pi * x0)
    # the faces x = 0 and x = 1 exactly (sin(pi) is 1.2e-16, not 0)
    nodes[:, :, 0, 0] = 0.0
    nodes[:, :, -1, 0] = 1.0
    return nodes


def write(path, nodes, kind, args):
    tmp = path + ".tmp"
    with h5py.File(tmp, "w") as f:
        f.create_dataset("x", data=np.ascontiguousarray(nodes, dtype=np.float64))
        f["x"].attrs["units"] = "length"
        f.attrs["generator"] = "tools/make_grid.py " + kind
        f.attrs["arguments"] = " ".join(sys.argv[1:])
        nk, nj, ni = (s - 1 for s in nodes.shape[:3])
        f.attrs["ni"], f.attrs["nj"], f.attrs["nk"] = ni, nj, nk
    os.replace(tmp, path)
    print("wrote %s: %s grid, %d x %d x %d cells, x in [%g, %g] x [%g, %g] x [%g, %g]"
          % (path, kind, ni, nj, nk, nodes[..., 0].min(), nodes[..., 0].max(), nodes[..., 1].min(),
             nodes[..., 1].max(), nodes[..., 2].min(), nodes[..., 2].max()))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="kind", required=True)
    for kind in ("box", "perturb"):
        p = sub.add_parser(kind)
        p.add_argument("--ni", type=int, required=True)
        p.add_argument("--nj", type=int, required=True)
        p.add_argument("--nk", type=int, required=True)
        p.add_argument("--xmin", type=float, nargs=3, default=[0.0, 0.0, 0.0])
        p.add_argument("--xmax", type=float, nargs=3, default=[1.0, 1.0, 1.0])
        if kind == "perturb":
            p.add_argument("--fraction", type=float, required=True,
                           help="largest move as a fraction of the cell size, in [0, 0.5)")
            p.add_argument("--seed", type=int, default=1)
        p.add_argument("--out", required=True)
    p = sub.add_parser("saltzman")
    p.add_argument("--ni", type=int, default=100)
    p.add_argument("--nj", type=int, default=10)
    p.add_argument("--dz", type=float, default=0.01, help="thickness of the one cell in z (default 0.01)")
    p.add_argument("--out", required=True)
    a = ap.parse_args()

    if a.ni < 1 or a.nj < 1 or getattr(a, "nk", 1) < 1:
        ap.error("ni, nj and nk must be >= 1")
    if a.kind == "saltzman":
        if not a.dz > 0:
            ap.error("--dz must be > 0")
        nodes = saltzman(a.ni, a.nj, a.dz)
    else:
        if not all(hi > lo for lo, hi in zip(a.xmin, a.xmax)):
            ap.error("--xmax must be above --xmin in every direction")
        nodes = box_nodes(a.ni, a.nj, a.nk, a.xmin, a.xmax)
        if a.kind == "perturb":
            if not 0.0 <= a.fraction < 0.5:
                ap.error("--fraction must be in [0, 0.5)")
            nodes = perturb(nodes, a.fraction, a.seed)
    write(a.out, nodes, a.kind, a)
    return 0


if __name__ == "__main__":
    sys.exit(main())
