#!/usr/bin/python3
"""Grid files for the &grid file tests (tests/CMakeLists.txt), written to DIR
next to the decks of tests/decks/grid/ that the build copies there:

    make_test_grids.py TOOLS DIR

Good grids by tools/make_grid.py (its command line is what is tested):
perturb.h5 (6 x 5 x 4 cells, nodes moved by up to 0.3 of a cell, seed 3),
box.h5 (8 x 6 x 4 cells on [0,1.2] x [0,1] x [0,0.8]), saltzman.h5 (the
Saltzman piston's 100 x 10 grid), sphere_perturb.h5 (20^3 cells, moved by up
to 0.3 of a cell, seed 5). Bad ones made from perturb.h5 with h5py: no_x.h5
(the dataset named y), nan_x.h5 (a NaN coordinate at node (2, 1, 3)),
tangled.h5 (node (3, 2, 2) pushed through its neighbours: cells around it
turned inside out), pushed.h5 (node (3, 2, 2) pushed 1.2 cells along i, past
node (4, 2, 2): every cell keeps a positive volume, but the cells around it
overlap their neighbours), int_x.h5 (integer coordinates); not_hdf5.h5 is text;
slabs.h5 (a box of 60 x 60 x 290 cells, more than one slab of 2^20 nodes,
node (3, 2, 286) of the second slab pushed past node (4, 2, 286));
perturb_points.txt (2000 points drawn uniformly in [0.001, 0.999]^3, seed 7,
for particles_perturb.nml).
"""
import os
import subprocess
import sys

tools, out = sys.argv[1], sys.argv[2]
sys.path.insert(0, tools)
import debian_python  # noqa: E402  tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("h5py", "numpy")
import h5py  # noqa: E402
import numpy as np  # noqa: E402

os.makedirs(out, exist_ok=True)
make = [sys.executable, os.path.join(tools, "make_grid.py")]


def run(*args):
    subprocess.run(make + list(args), check=True)


run("perturb", "--ni", "6", "--nj", "5", "--nk", "4", "--fraction", "0.3", "--seed", "3",
    "--out", os.path.join(out, "perturb.h5"))
run("box", "--ni", "8", "--nj", "6", "--nk", "4", "--xmax", "1.2", "1", "0.8", "--out", os.path.join(out, "box.h5"))
run("saltzman", "--out", os.path.join(out, "saltzman.h5"))
run("perturb", "--ni", "20", "--nj", "20", "--nk", "20", "--fraction", "0.3", "--seed", "5",
    "--out", os.path.join(out, "sphere_perturb.h5"))

x = h5py.File(os.path.join(out, "perturb.h5"), "r")["x"][...]
with h5py.File(os.path.join(out, "no_x.h5"), "w") as f:
    f["y"] = x
bad = x.copy()
bad[3, 1, 2, 0] = np.nan          # node (i, j, k) = (2, 1, 3)
with h5py.File(os.path.join(out, "nan_x.h5"), "w") as f:
    f["x"] = bad
bad = x.copy()
bad[2, 2, 3] = x[2, 2, 3] + 2.5 * (x[2, 2, 4] - x[2, 2, 3])   # node (3, 2, 2) past node (4, 2, 2)
with h5py.File(os.path.join(out, "tangled.h5"), "w") as f:
    f["x"] = bad
bad = x.copy()
bad[2, 2, 3] = x[2, 2, 3] + 1.2 * (x[2, 2, 4] - x[2, 2, 3])   # node (3, 2, 2) just past node (4, 2, 2)
with h5py.File(os.path.join(out, "pushed.h5"), "w") as f:
    f["x"] = bad
with h5py.File(os.path.join(out, "int_x.h5"), "w") as f:
    f["x"] = np.rint(x).astype(np.int32)
run("box", "--ni", "60", "--nj", "60", "--nk", "290", "--out", os.path.join(out, "slabs.h5"))
with h5py.File(os.path.join(out, "slabs.h5"), "r+") as f:
    x = f["x"][286, 2, 3:5]
    f["x"][286, 2, 3] = x[0] + 2.5 * (x[1] - x[0])   # node (3, 2, 286) past node (4, 2, 286)
np.savetxt(os.path.join(out, "perturb_points.txt"), np.random.default_rng(7).uniform(0.001, 0.999, (2000, 3)))
with open(os.path.join(out, "not_hdf5.h5"), "w") as f:
    f.write("this is not an HDF5 file\n")
print("grid files written to", out)
