#!/usr/bin/env python3
"""Paper Sect. 7.6, Fig. 31: the pressure histories of the fluid gauge g and
of the tracked shell particle p, for one or more runs of
input/steel_shell.nml (e.g. the decoupled and the original schemes).

    shell_histories.py LABEL=DIR/NAME [LABEL=DIR/NAME ...] --png FILE
                       [--time-scale 1000] [--time-unit us] [--p-scale 1e-3] [--p-unit GPa]

Each DIR/NAME names a run's output prefix: DIR/NAME_gauges.txt (the first
gauge's pressure column) and DIR/NAME_tracks.txt (the first tracked
particle's pressure -trace(sigma)/3). Both columns are found by their
names in the files' last header row. Times and pressures are multiplied by
the scales before plotting (the deck's units are ms and MPa: the defaults
give us and GPa). Prints each run's peak of both. Run with /usr/bin/python3
(matplotlib).
"""
import argparse
import sys


def column(path, name):
    """Time and the column `name` of a gauges/tracks file."""
    header, rows = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                header = line[1:].split()
            elif line.strip():
                rows.append([float(w) for w in line.split()])
    if header is None or name not in header:
        sys.exit(f"{path}: no column {name}")
    k = header.index(name)
    return [r[0] for r in rows], [r[k] for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", help="LABEL=DIR/NAME")
    ap.add_argument("--png", required=True)
    ap.add_argument("--time-scale", type=float, default=1000.0)
    ap.add_argument("--time-unit", default="us")
    ap.add_argument("--p-scale", type=float, default=1.0e-3)
    ap.add_argument("--p-unit", default="GPa")
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for run in a.runs:
        label, _, prefix = run.partition("=")
        for ax, suffix, col, what in ((ax1, "_gauges.txt", "pressure_1", "gauge g (fluid)"),
                                      (ax2, "_tracks.txt", "pressure_1", "particle p (shell)")):
            t, p = column(prefix + suffix, col)
            t = [v * a.time_scale for v in t]
            p = [v * a.p_scale for v in p]
            ax.plot(t, p, label=label)
            k = max(range(len(p)), key=lambda i: p[i])
            print(f"{label:12s} {what:20s} peak {p[k]:.4g} {a.p_unit} at {t[k]:.4g} {a.time_unit}")
            ax.set_title(what)
    for ax in (ax1, ax2):
        ax.set_xlabel(f"time ({a.time_unit})")
        ax.set_ylabel(f"pressure ({a.p_unit})")
        ax.grid(True, alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)
    print(f"wrote {a.png}")


if __name__ == "__main__":
    main()
