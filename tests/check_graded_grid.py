#!/usr/bin/env python3
"""The node planes of a graded box (&grid spacing_x, spacing_y, spacing_z).

    check_graded_grid.py FRAME AXIS LO HI C1 W1 [C2 W2 ...]

FRAME is a frame of the run (frame 0: the grid as built); AXIS 1, 2 or 3;
LO, HI the box's extent along it; (C, W) the deck's pairs (coordinate, cell
width). Checks, from the frame's node coordinates alone:
- the grid is a box graded along the axis: every node of a plane i holds
  the same coordinate (exactly: the planes are placed once), the first and
  last planes at LO and HI exactly, the planes increasing;
- the widths have the shape the pairs give: with w(x) the width the pairs
  interpolate linearly (held beyond the first and last pair), each cell's
  width over w at its midpoint is the same factor to 1e-3 relative. The
  nodes sit at equal steps D of the integral of 1/w, so where w grows
  linearly with slope s every cell has width/w(mid) = 2 tanh(s D/2)/s =
  D (1 - (s D)^2/12 + ...): one factor in each stretch between pairs, and
  from stretch to stretch within (s D)^2/12 (1e-3 for s D up to 0.1; the
  test decks have one stretch per axis, where the spread is round-off).
Exit status 0 when all hold.
"""
import sys

import h5py
import numpy as np


def main():
    frame, axis = sys.argv[1], int(sys.argv[2])
    lo, hi = float(sys.argv[3]), float(sys.argv[4])
    pairs = [float(v) for v in sys.argv[5:]]
    xc = np.array([lo] + pairs[0::2] + [hi])
    wc = np.array([pairs[1]] + pairs[1::2] + [pairs[-1]])
    with h5py.File(frame, "r") as f:
        x = f["x"][()]          # (nk+1, nj+1, ni+1, 3)
    c = x[..., axis - 1]
    # the coordinate along the axis varies with the axis' index only
    lay = np.moveaxis(c, 3 - axis, 0)     # h5py's axis order is k, j, i
    planes = lay.reshape(lay.shape[0], -1)
    ok = True
    if not np.all(planes == planes[:, :1]):
        print("FAIL: a node plane is not flat")
        ok = False
    p = planes[:, 0]
    if p[0] != lo or p[-1] != hi:
        print(f"FAIL: end planes at {p[0]!r}, {p[-1]!r}, not {lo!r}, {hi!r}")
        ok = False
    h = np.diff(p)
    if not np.all(h > 0):
        print("FAIL: planes not increasing")
        ok = False
    mid = 0.5 * (p[1:] + p[:-1])
    ratio = h / np.interp(mid, xc, wc)
    spread = (ratio.max() - ratio.min()) / ratio.mean()
    print(f"axis {axis}: {len(h)} cells, widths {h.min():.6g} to {h.max():.6g}, width/w(mid) "
          f"{ratio.mean():.6f} (spread {spread:.2e}, <= 1e-3)")
    if not spread <= 1e-3:
        print("FAIL: the widths do not follow the pairs' shape")
        ok = False
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
