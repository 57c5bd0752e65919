#!/usr/bin/env python3
"""A picture of one particle body's damage: its particles in a frame,
projected on two planes and coloured by the `damage` field (HJC or the
bilinear tensile fracture), one row of two panels per run (paper Sect. 7.7,
Fig. 35: the crack down the centre column, the damage at its ends).

    body_damage_png.py --run LABEL FRAME [--run LABEL FRAME ...] --body 1
                       --out PNG [--views xz,yz] [--mirror y] [--title TEXT]

Each panel draws the body's particles seen along the axis its view leaves
out (xz: from the side, looking along y; yz: from the front, looking along
x), the particles nearer the viewer on top, so the face the viewer sees is
drawn, each a square of its own size (the cube root of its volume).
`--mirror y` draws the body's mirror image in y = 0 too (a half model's
symmetry plane). Prints, per run, the frame time and the body's particles above
damage 0.1, 0.5 and at 1. Read with h5py, drawn with matplotlib (run with
/usr/bin/python3). The frame must hold the `damage` and `body` particle
fields (&output particle_fields).
"""
import argparse
import sys

import h5py
import numpy as np

AXES = {"x": 0, "y": 1, "z": 2}


def load(frame, body, mirror):
    """(t, positions, damage, sizes) of the body's particles in a frame (and
    their mirror images in the plane of axis `mirror` = 0)."""
    with h5py.File(frame, "r") as f:
        p = f["particles"]
        for name in ("damage", "body", "volume"):
            if name not in p:
                sys.exit("%s: no particles/%s (add it to &output particle_fields)" % (frame, name))
        keep = p["body"][()] == body
        if not keep.any():
            sys.exit("%s: no particle of body %d" % (frame, body))
        x, d, h = p["x"][()][keep], p["damage"][()][keep], np.cbrt(p["volume"][()][keep])
        t = float(f["time"][()])
    if mirror:
        xm = x.copy()
        xm[:, AXES[mirror]] *= -1
        x, d, h = np.vstack([x, xm]), np.concatenate([d, d]), np.concatenate([h, h])
    return t, x, d, h


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--run", nargs=2, action="append", metavar=("LABEL", "FRAME"), required=True)
    ap.add_argument("--body", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--views", default="xz,yz", help="comma-separated planes (two axes each), default xz,yz")
    ap.add_argument("--mirror", choices=sorted(AXES), help="draw the mirror image in this axis' zero plane too")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    views = a.views.split(",")
    if any(len(v) != 2 or v[0] not in AXES or v[1] not in AXES or v[0] == v[1] for v in views):
        sys.exit("--views: planes such as xz,yz")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = [(label, *load(frame, a.body, a.mirror)) for label, frame in a.run]
    ext = np.ptp(np.vstack([r[2] for r in runs]), axis=0) + 1e-300
    widths = [ext[AXES[v[0]]] / ext[AXES[v[1]]] for v in views]
    height = 5.0
    fig, axs = plt.subplots(len(runs), len(views), squeeze=False,
                            figsize=(height * sum(widths) + 1.5 * len(views) + 1.2, (height + 1.4) * len(runs)),
                            gridspec_kw={"width_ratios": widths, "wspace": 1.2, "hspace": 0.3})
    for row, (label, t, x, d, h) in enumerate(runs):
        own = d[:len(d) // 2] if a.mirror else d        # the counts leave the mirror images out
        print("%s: t = %g, %d particles, damage > 0.1: %d, > 0.5: %d, = 1: %d"
              % (label, t, len(own), (own > 0.1).sum(), (own > 0.5).sum(), (own >= 1).sum()))
        for col, v in enumerate(views):
            i, j = AXES[v[0]], AXES[v[1]]
            depth = 3 - i - j
            order = np.argsort(-x[:, depth])       # the viewer on the low side of the axis left out
            ax = axs[row, col]
            points = 72.0 * height / ext[j]        # points per unit length, about
            sc = ax.scatter(x[order, i], x[order, j], c=d[order], s=(points * h[order]) ** 2, marker="s",
                            cmap="inferno_r", vmin=0, vmax=1, linewidths=0)
            ax.set_aspect("equal")
            ax.locator_params(axis="x", nbins=2)
            ax.tick_params(axis="x", labelrotation=90)
            ax.set_xlabel(v[0])
            ax.set_ylabel(v[1])
            ax.set_title("%s\nt = %.3g, seen along -%s" % (label, t, "xyz"[depth]), fontsize=8)
        fig.colorbar(sc, ax=axs[row, :].tolist(), label="damage", shrink=0.8)
    if a.title:
        fig.suptitle(a.title)
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
