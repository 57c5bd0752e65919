#!/usr/bin/env python3
"""Counts the pixels of tools/render_frame.sh's picture of a quasi-2D
particle run (viz_render_particles.sh):

    check_render_particles.py PNG FRAME.h5 POINT_PIXELS

- particle pixels: red above green and above blue by 0.2 (the particles'
  colour map runs from orange (1, 0.55, 0) through red to dark red; no
  colour of viridis, the grid's map, and no grey passes, which is checked
  here on 256 viridis samples). Counted in the picture's upper 85 % and
  left 75 % (the particles' bar lies below, the grid's on the right).
  Expected: the particles seen face on, their distinct in-plane positions
  (particles one behind the other across the thin direction cover the same
  pixels) each a disc of POINT_PIXELS diameter, pi/4 POINT_PIXELS^2 each.
  Bounds 0.5 and 1.3 times that: the spheres' shaded rims turn dark (below
  the threshold) and antialiasing blurs the edge (measured 0.761 on the
  particles_rest block, 48 positions of 18.9-pixel points, 800 x 600).
- grid pixels: within 0.08 of a viridis colour times 0.6 .. 1 (the
  light's shading; measured 0.78) and not grey; at least
  100,000 (an 800 x 600 picture of the 1 x 1 slice: the slice is fitted to
  600/1.4 = 428 pixels high, 183,000 pixels, less the block, about 22,000,
  and the cell edges, about 9,000).
Exit status 0 pass, 1 fail.
"""
import sys

import h5py
import matplotlib
import matplotlib.image
import numpy as np

fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


def particle_like(rgb):
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return (r > g + 0.2) & (r > b + 0.2)


def main():
    png, frame, size = sys.argv[1], sys.argv[2], float(sys.argv[3])
    img = matplotlib.image.imread(png)[..., :3].astype(float)
    h, w, _ = img.shape
    viridis = matplotlib.colormaps["viridis"](np.linspace(0.0, 1.0, 256))[:, :3]
    check(not particle_like(viridis).any(), "no viridis colour passes the particle test")
    greys = np.linspace(0.0, 1.0, 256)[:, None].repeat(3, axis=1)
    check(not particle_like(greys).any(), "no grey passes the particle test")

    area = img[: int(0.85 * h), : int(0.75 * w)]
    npart = int(particle_like(area).sum())
    with h5py.File(frame, "r") as f:
        x = f["particles/x"][()]
    # the slice's normal: the thinnest extent of the grid (quasi-2D: z here)
    with h5py.File(frame, "r") as f:
        nodes = f["x"][()].reshape(-1, 3)
    normal = int(np.argmin(nodes.max(axis=0) - nodes.min(axis=0)))
    inplane = np.delete(x, normal, axis=1)
    spots = len(np.unique(np.round(inplane, 9), axis=0))
    expected = spots * np.pi / 4.0 * size ** 2
    ratio = npart / expected
    check(0.5 <= ratio <= 1.3,
          f"{npart} particle-coloured pixels, {ratio:.3f} of {spots} discs of {size:g} pixels "
          f"({expected:.0f}); bounds 0.5 .. 1.3")

    # (the headlight shades the face-on slice: a viridis colour times 0.6 .. 1)
    shades = np.concatenate([k * viridis[::8] for k in np.arange(0.6, 1.001, 0.05)])
    d = np.min(np.linalg.norm(area[:, :, None, :] - shades[None, None, :, :], axis=3), axis=2)
    grey = area.max(axis=2) - area.min(axis=2) < 0.1
    ngrid = int(((d < 0.08) & ~grey).sum())
    check(ngrid >= 100000, f"{ngrid} grid pixels in viridis colours (at least 100000)")
    print("FAIL" if fails else "PASS: the grid and the particles are coloured, each by its own map")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
