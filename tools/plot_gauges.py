#!/usr/bin/python3
"""Plot gauge histories (or the energy history) of an lsalepm run to PNG.

    plot_gauges.py FILE [--out PNG] [--fields density,pressure,...] [--gauges 1,3]

FILE is `<dir>/<name>_gauges.txt` or `<dir>/<name>_history.txt`. Both are
plain columns whose last `#` header row names them: `time`, then for the
gauges `<field>_<g>` (`cell_<g>` is the cell that contains gauge g's point,
not plotted), for the history `kinetic internal boundary_work total drift`.
One panel per field, one line per gauge, time on the x axis; gauge points
(the `# gauge g at x y z` header lines) label the lines. The default output
is FILE with `.png` in place of `.txt`. Uses Debian's Python (numpy,
matplotlib): run it as `/usr/bin/python3 tools/plot_gauges.py` or directly.
"""
import argparse
import math
import re
import sys

import numpy as np


def read_table(path):
    """(names, data, gauge points {g: 'x y z'}) of a gauge or history file."""
    names, points = None, {}
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            text = line[1:].strip()
            m = re.match(r"gauge (\d+) at\s+(\S+)\s+(\S+)\s+(\S+)", text)
            if m:
                points[int(m.group(1))] = " ".join(f"{float(v):.4g}" for v in m.groups()[1:])
            elif text.split()[:1] == ["time"]:
                names = text.split()
    if names is None:
        raise SystemExit(f"{path}: no header row naming the columns (a '# time ...' line)")
    data = np.loadtxt(path, comments="#", ndmin=2)
    if data.size == 0:
        raise SystemExit(f"{path}: no rows")
    if data.shape[1] != len(names):
        raise SystemExit(f"{path}: {data.shape[1]} columns but the header names {len(names)}")
    return names, data, points


def series(names):
    """{field: [(gauge or None, column)]} in the order of the columns."""
    out = {}
    for col, name in enumerate(names[1:], start=1):
        m = re.fullmatch(r"(.+)_(\d+)", name)
        field, gauge = (m.group(1), int(m.group(2))) if m else (name, None)
        if field == "cell":
            continue
        out.setdefault(field, []).append((gauge, col))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file", help="<name>_gauges.txt or <name>_history.txt")
    ap.add_argument("--out", help="PNG to write (default: FILE with .png)")
    ap.add_argument("--fields", help="comma-separated fields to plot (default: all)")
    ap.add_argument("--gauges", help="comma-separated gauge numbers to plot (default: all)")
    args = ap.parse_args(argv)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names, data, points = read_table(args.file)
    fields = series(names)
    if args.fields:
        want = [f.strip() for f in args.fields.split(",")]
        unknown = [f for f in want if f not in fields]
        if unknown:
            raise SystemExit(f"unknown field(s) {', '.join(unknown)}; the file has {', '.join(fields)}")
        fields = {f: fields[f] for f in want}
    if args.gauges:
        keep = {int(g) for g in args.gauges.split(",")}
        fields = {f: [(g, c) for g, c in s if g is None or g in keep] for f, s in fields.items()}
    if not fields:
        raise SystemExit("nothing to plot")
    out = args.out or re.sub(r"\.txt$", "", args.file) + ".png"

    n = len(fields)
    ncol = 1 if n == 1 else 2
    nrow = math.ceil(n / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(6.0 * ncol, 2.6 * nrow), sharex=True, squeeze=False)
    t = data[:, 0]
    for ax, (field, cols) in zip(axes.flat, fields.items()):
        for gauge, col in cols:
            label = None if gauge is None else f"gauge {gauge}" + (f" ({points[gauge]})" if gauge in points else "")
            ax.plot(t, data[:, col], lw=1.2, label=label)
        ax.set_ylabel(field.replace("_", " "))
        ax.grid(alpha=0.3)
        if any(g is not None for g, _ in cols) and len(cols) > 1:
            ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    for i, ax in enumerate(list(axes.flat)[:n]):
        if i + ncol >= n:  # lowest visible panel of its column
            ax.set_xlabel("time")
            ax.tick_params(labelbottom=True)
    fig.suptitle(args.file, fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    ngauge = len({g for s in fields.values() for g, _ in s if g is not None})
    print(f"wrote {out}: {n} panel(s) ({', '.join(fields)}), {ngauge or 'no'} gauge(s), {len(t)} rows")
    return 0


if __name__ == "__main__":
    sys.exit(main())
