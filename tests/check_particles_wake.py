#!/usr/bin/env python3
"""The gas behind a plate one cell thick keeps its state
(tests/decks/particles_plate_wake.nml).

    check_particles_wake.py PREFIX X0 X1 Y1 RHO_MIN U_MAX

PREFIX_NNNNN.h5 are the frames of a run. In every frame, the cells whose
centres lie in X0 < x < X1, y < Y1 (the wake's first cells, at the floor)
must hold a density of at least RHO_MIN, and the nodes with X0 < x <= X1,
y <= Y1 move at most at U_MAX. Run with /usr/bin/python3 (Debian numpy and
h5py).
"""
import glob
import sys

import h5py
import numpy as np


def main():
    prefix = sys.argv[1]
    x0, x1, y1, rho_min, u_max = (float(v) for v in sys.argv[2:7])
    frames = sorted(glob.glob(prefix + "_[0-9][0-9][0-9][0-9][0-9].h5"))
    if len(frames) < 2:
        print("FAIL: fewer than two frames")
        sys.exit(1)
    ok = True
    for fn in frames:
        with h5py.File(fn, "r") as f:
            t = float(f["time"][()])
            x = f["x"][()]
            nz, ny, nx = x.shape[:3]
            x = x.reshape(-1, 3)
            u = np.linalg.norm(f["velocity"][()].reshape(-1, 3), axis=1)
            rho = f["density"][()].reshape(-1)
        # cell centres: the mean of each cell's 8 nodes
        xn = x.reshape(nz, ny, nx, 3)
        xc = sum(xn[a:nz - 1 + a, b:ny - 1 + b, c:nx - 1 + c] for a in (0, 1) for b in (0, 1)
                 for c in (0, 1)) / 8.0
        xc = xc.reshape(-1, 3)
        cells = (xc[:, 0] > x0) & (xc[:, 0] < x1) & (xc[:, 1] < y1)
        nodes = (x[:, 0] > x0) & (x[:, 0] <= x1) & (x[:, 1] <= y1)
        if not cells.any() or not nodes.any():
            print(f"FAIL: t = {t:g}: no wake cell or node in the box")
            sys.exit(1)
        rmin = float(rho[cells].min())
        umax = float(u[nodes].max())
        good = rmin >= rho_min and umax <= u_max
        ok = ok and good
        print(f"t = {t:.4g}: wake density min {rmin:.4g} (at least {rho_min:g}), node speed max {umax:.4g} "
              f"(at most {u_max:g}){'' if good else '  FAIL'}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
