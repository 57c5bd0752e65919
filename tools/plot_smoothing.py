#!/usr/bin/python3
"""Plot the smoothing benchmark (paper Sect. 7.1, Fig. 16) from the CSV that
tests/bench_smooth writes (columns iteration, method, q_min, seconds,
wall_seconds; seconds is cumulative CPU time, iteration 0 the initial grid).

Left: worst cell quality Q_min against CPU time (as Fig. 16). Middle: 1 - Q_min
against CPU time on a log scale. Right: 1 - Q_min against iterations, with the
tangled variants dashed. The dotted line is the target Q_min = 0.9999.

Usage: plot_smoothing.py CSV [--out PNG]     (default PNG: CSV with .png)
"""
import debian_python  # tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("matplotlib")

import argparse
import csv
import os
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LABELS = {
    "getme": "GETMe (original)",
    "modified_getme": "modified GETMe",
    "weighted_average": "weighted average",
    "combined": "combined",
}
Q_TARGET = 0.9999


def read(path):
    runs = OrderedDict()
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            r = runs.setdefault(row["method"], {"it": [], "q": [], "t": []})
            r["it"].append(int(row["iteration"]))
            r["q"].append(float(row["q_min"]))
            r["t"].append(float(row["seconds"]))
    return runs


def label(method):
    if method.startswith("combined_tangled_"):
        return "combined, tangled (amplitude %s)" % method.rsplit("_", 1)[1]
    return LABELS.get(method, method)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--out")
    a = ap.parse_args()
    runs = read(a.csv)
    if not runs:
        sys.exit("plot_smoothing: no rows in %s" % a.csv)
    out = a.out or os.path.splitext(a.csv)[0] + ".png"

    fig, (ax1, ax3, ax2) = plt.subplots(1, 3, figsize=(17, 4.8))
    for method, r in runs.items():
        tangled = method.startswith("combined_tangled_")
        style = "--" if tangled else "-"
        gap = [max(1.0 - q, 1e-7) for q in r["q"]]
        if not tangled:
            ax1.plot(r["t"], r["q"], style, marker=".", label=label(method))
            ax3.semilogy(r["t"], gap, style, marker=".", label=label(method))
        ax2.semilogy(r["it"], gap, style, marker=".", label=label(method))
    ax1.axhline(Q_TARGET, color="k", lw=0.8, ls=":")
    ax1.set_xlabel("CPU time [s]")
    ax1.set_ylabel("worst cell quality $Q_{min}$ (Eq. 46)")
    ax1.set_ylim(top=1.005)
    ax1.grid(alpha=0.3)
    ax1.legend()
    ax1.set_title("$Q_{min}$ against CPU time (cf. Fig. 16)")
    for ax, xl in ((ax3, "CPU time [s]"), (ax2, "iteration")):
        ax.axhline(1.0 - Q_TARGET, color="k", lw=0.8, ls=":")
        ax.set_xlabel(xl)
        ax.set_ylabel("$1 - Q_{min}$")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    ax3.set_title("$1 - Q_{min}$ against CPU time")
    ax2.set_title("$1 - Q_{min}$ against iterations")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("plot_smoothing: wrote", out)


if __name__ == "__main__":
    main()
