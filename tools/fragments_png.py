#!/usr/bin/env python3
"""A picture of the fragments of particle bodies (paper Sect. 7.6, Fig. 32:
the shell's fragments), one panel per run, side by side.

    fragments_png.py --run LABEL FRAME0 FRAME [--run LABEL FRAME0 FRAME ...]
                     --out PNG [--columns C] [--main 0.02] [--bond 1.1] [--title TEXT]

Each run is its first frame (t = 0: the bonds) and the frame to draw. The
fragments are those of tools/fragments.py (the same bonds, failure flags and
main-fragment share): in the x-y plane, each main fragment in its own
colour (the largest first) over the smaller fragments in grey and the
failed particles (the cracks) as small black points; particles that left
the grid are not drawn. Prints, per panel, its time and its counts of main
fragments, fragments and failed particles. The panels fill rows of C (default: one
row). Read with h5py, drawn with
matplotlib (run with /usr/bin/python3).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.dont_write_bytecode = True
from fragments import bonds, components, load  # noqa: E402


def panel(frame0, frame, bond, main):
    """(t, x, labels ranked by size (0 the largest; -1 failed or gone), the
    number of main fragments, fragments, failed) of one run's frame."""
    _, x0, _, ids0, more0 = load(frame0, extra=True)
    pairs, _ = bonds(x0, bond, more0["body"])
    t, x, failed, gone = load(frame, ids0)
    labels = components(len(x0), pairs, ~failed & ~gone)
    ids, sizes = np.unique(labels[labels >= 0], return_counts=True)
    rank = np.full(labels.shape, -1)
    for k, c in enumerate(ids[np.argsort(-sizes, kind="stable")]):
        rank[labels == c] = k
    nmain = int((sizes >= main * len(x0)).sum())
    return t, x, rank, failed & ~gone, nmain, len(ids)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--run", nargs=3, action="append", metavar=("LABEL", "FRAME0", "FRAME"), required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--bond", type=float, default=1.1)
    ap.add_argument("--main", type=float, default=0.02)
    ap.add_argument("--title", default="")
    ap.add_argument("--columns", type=int, default=0, help="panels per row (default: all in one row)")
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    colours = plt.get_cmap("tab10").colors
    ncol = a.columns if a.columns > 0 else len(a.run)
    nrow = -(-len(a.run) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 4.4 * nrow), squeeze=False)
    for ax in axes.ravel()[len(a.run):]:
        ax.set_visible(False)
    for ax, (label, frame0, frame) in zip(axes.ravel(), a.run):
        t, x, rank, failed, nmain, nfrag = panel(frame0, frame, a.bond, a.main)
        small = rank >= nmain
        ax.scatter(x[failed, 0], x[failed, 1], s=0.2, c="k", linewidths=0)
        ax.scatter(x[small, 0], x[small, 1], s=0.5, c="0.6", linewidths=0)
        for k in range(nmain):
            sel = rank == k
            ax.scatter(x[sel, 0], x[sel, 1], s=0.5, color=colours[k % len(colours)], linewidths=0)
        ax.set_aspect("equal")
        ax.set_title(f"{label}\nt = {t:.4g}: {nmain} main fragments, {int(failed.sum())} failed", fontsize=9)
        ax.tick_params(labelsize=8)
        print(f"{label}: t = {t:.6g}, {nmain} main fragments, {nfrag} fragments, {int(failed.sum())} failed")
    if a.title:
        fig.suptitle(a.title, fontsize=10)
    fig.tight_layout()
    fig.savefig(a.out, dpi=150)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
