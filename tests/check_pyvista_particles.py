#!/usr/bin/env python3
"""A particle run's two XDMF series read with pyvista (VTK's XDMF reader),
the last frame checked against h5py reads of it (issue 38):

    check_pyvista_particles.py OUTDIR NAME

- NAME.xdmf at the last time: the grid, as many cells as the frame's
  density, its density values the frame's (cell order i fastest);
- NAME_particles.xdmf at the last time: as many points as the frame's
  particles, at particles/x, with their mass.
Exits 77 (skipped) without pyvista (not packaged in Debian 12); 0 pass,
1 fail.
"""
import os
import sys

import h5py
import numpy as np

try:
    import pyvista as pv
except ImportError:
    print("SKIP: no pyvista")
    sys.exit(77)

fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


def last(path):
    """The dataset of the series `path` at its last time (a multiblock's
    first block)."""
    reader = pv.XdmfReader(os.path.abspath(path))
    times = list(reader.time_values)
    if times:
        reader.set_active_time_value(times[-1])
    data = reader.read()
    if isinstance(data, pv.MultiBlock):
        data = data[0]
    return data


def main():
    outdir, name = sys.argv[1], sys.argv[2]
    frames = sorted(f for f in os.listdir(outdir) if f.startswith(name + "_") and f.endswith(".h5")
                    and f[len(name) + 1:-3].isdigit())
    with h5py.File(os.path.join(outdir, frames[-1]), "r") as h:
        rho = h["density"][()].ravel()  # (nk, nj, ni) in C order: i fastest
        x, m = h["particles/x"][()], h["particles/mass"][()]
    grid = last(os.path.join(outdir, name + ".xdmf"))
    check(grid.n_cells == rho.size, f"grid: {grid.n_cells} cells, the frame's {rho.size}")
    if "density" in grid.cell_data:
        check(np.array_equal(np.asarray(grid.cell_data["density"]), rho), "grid: density is the frame's")
    else:
        check(False, f"grid: no density among {list(grid.cell_data.keys())}")
    parts = last(os.path.join(outdir, name + "_particles.xdmf"))
    check(parts.n_points == len(x), f"particles: {parts.n_points} points, the frame's {len(x)}")
    check(np.array_equal(np.asarray(parts.points), x), "particles: points are the frame's particles/x")
    if "mass" in parts.point_data:
        check(np.array_equal(np.asarray(parts.point_data["mass"]), m), "particles: mass is the frame's")
    else:
        check(False, f"particles: no mass among {list(parts.point_data.keys())}")
    print("FAIL" if fails else "PASS: pyvista reads the grid's and the particles' series")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
