#!/usr/bin/env python3
"""A particle run's XDMF series read with meshio (Debian's python3-meshio
7.0, meshio.xdmf.TimeSeriesReader), checked against h5py reads of the same
frames (issue 38):

    check_meshio_particles.py OUTDIR NAME

- NAME_particles.xdmf: as many time steps as frames, each step's time the
  frame's; the first and the last frame's particles (their counts differ
  when particles left the grid: the reader's mesh is taken from that
  step's grid, `reader.mesh_grid = reader.collection[k]`) give the frame's
  particles/x as points, one vertex cell each, and velocity, mass, body
  and stress (6 components, Tensor6) equal to the frame's datasets, bit
  for bit;
- NAME.xdmf: meshio's reader accepts the file (its Information elements,
  the temporal collection, the field data behind an XInclude) with one
  step per frame; the grid itself is a structured 3DSMesh, which meshio
  7 does not read (no topology DataItem): checked as that known refusal,
  so that a meshio that learns it shows here.
Exits 77 (skipped) without meshio; 0 pass, 1 fail.
"""
import os
import sys

import h5py
import numpy as np

try:
    import meshio
except ImportError:
    print("SKIP: no meshio (python3-meshio)")
    sys.exit(77)

fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


def frame_files(xdmf):
    import xml.etree.ElementTree as ET
    files = []
    for g in ET.parse(xdmf).getroot().iter("Grid"):
        if g.get("GridType") == "Uniform":
            item = g.find("Geometry/DataItem")
            files.append(None if item is None else item.text.strip().split(":")[0])
    return files


def main():
    outdir, name = sys.argv[1], sys.argv[2]
    grid_path = os.path.join(outdir, name + ".xdmf")
    part_path = os.path.join(outdir, name + "_particles.xdmf")
    frames = [f for f in frame_files(grid_path)]
    with meshio.xdmf.TimeSeriesReader(part_path) as r:
        check(r.num_steps == len(frames), f"particles: {r.num_steps} steps, {len(frames)} frames")
        for k in sorted({0, r.num_steps - 1}):
            h = h5py.File(os.path.join(outdir, frames[k]), "r")
            r.mesh_grid = r.collection[k]  # this step's own particles
            points, cells = r.read_points_cells()
            t, pd, cd = r.read_data(k)
            x = h["particles/x"][()]
            tag = f"particles, step {k} ({frames[k]})"
            check(t == float(h["time"][()]), f"{tag}: time {t}")
            check(points.shape == x.shape and np.array_equal(points, x),
                  f"{tag}: {len(points)} points, the frame's {len(x)} particles/x")
            check(len(cells) == 1 and cells[0].type == "vertex" and len(cells[0].data) == len(x),
                  f"{tag}: one vertex cell per particle")
            for field in ("velocity", "mass", "body", "stress"):
                want = h["particles/" + field][()]
                got = pd.get(field)
                check(got is not None and got.shape == want.shape and np.array_equal(got, want),
                      f"{tag}: {field} {None if got is None else got.shape} equals the frame's")
            check(not cd, f"{tag}: no cell data")
    if len(frames) > 1:
        with h5py.File(os.path.join(outdir, frames[0]), "r") as a, \
                h5py.File(os.path.join(outdir, frames[-1]), "r") as b:
            print(f"note: {a['particles/x'].shape[0]} particles in the first frame, "
                  f"{b['particles/x'].shape[0]} in the last")
    with meshio.xdmf.TimeSeriesReader(grid_path) as r:
        check(r.num_steps == len(frames), f"grid: meshio opens the series, {r.num_steps} steps")
        try:
            r.read_points_cells()
            check(False, "grid: meshio now reads a 3DSMesh grid: read it here")
        except (meshio.ReadError, KeyError) as e:
            print(f"note: grid: meshio 7 reads no 3DSMesh topology ({type(e).__name__}: {e})")
    print("FAIL" if fails else "PASS: meshio reads the particles' series")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
