#!/usr/bin/env python3
"""Runs' blast answers at the gauges against Kingery-Bulmash (free air).

    blast_kb_plot.py FILE [FILE ...] --mass-kg W [--centre X Y Z]
        [--length-unit mm] [--pressure-unit GPa] [--time-unit us]
        [--reflection 1.8] [--label L ...] [--out blast_kb.png] [--csv T.csv]

Each FILE is either a run's <name>_blast.txt (modules/io/io_blast.f90: per
gauge its point x y z, arrival, peak overpressure, ...) or a gauge file
(<name>_gauges.txt, or the 1D pre-run's <name>_prerun_gauges.txt), whose
answers are computed by tools/blast_gauges.py's functions (same definitions
as _blast.txt: arrival when the overpressure first reaches --fraction of its
peak, 0.5 by default; overpressure over the first row's pressure). The gauge
positions come from the blast file's x y z columns, or from the gauge file's
header (`# gauge g at x y z`, or `# gauge g at radius R` in a pre-run file,
R then the distance itself); R is the distance from --centre (the charge
centre, deck units).

Units: the deck's length, pressure and time units (--length-unit mm|cm|m,
--pressure-unit GPa|MPa|kPa|Pa|bar|Mbar, --time-unit us|ms|s) convert R to
m, pressures to kPa and times to ms. Z = R / W^(1/3) (m/kg^(1/3)) with W the
free-air TNT mass --mass-kg.

Kingery-Bulmash: tools/kingery_bulmash.py. The reference is KB's fits of
the spherical free-air burst (column KB_free); beside it, the common
approximation of a free-air burst of W as a hemispherical surface burst of
W / F (Swisdak 1994's fits; F = --reflection, default 1.8, UFC 3-340-02),
column KB_F1.8. The table gives the run's difference from each, 100 (run /
KB - 1) %; the plot draws both curves (the free-air fits solid). A gauge
whose Z is outside a fit's range gets nan in its KB columns (and a note).

Writes the PNG (--out; peak overpressure in kPa against Z, log-log, and
arrival in ms against Z, log-log) and prints the table (also --csv).
"""
import argparse
import csv
import math
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import blast_gauges  # noqa: E402
import kingery_bulmash as kb  # noqa: E402

TO_M = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}
TO_KPA = {"GPa": 1e6, "MPa": 1e3, "kPa": 1.0, "Pa": 1e-3, "bar": 100.0, "Mbar": 1e8}
TO_MS = {"us": 1e-3, "ms": 1.0, "s": 1e3}


def header_lines(path):
    with open(path) as f:
        return [l.rstrip("\n") for l in f if l.startswith("#")]


def is_blast_file(path):
    return any(l.lstrip("#").split()[:4] == ["gauge", "x", "y", "z"] for l in header_lines(path))


def read_blast(path, centre):
    """{gauge: (distance, arrival, peak)} from a <name>_blast.txt (deck units)."""
    names = next(l.lstrip("#").split() for l in header_lines(path) if l.lstrip("#").split()[:4] == ["gauge", "x", "y", "z"])
    out = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        v = line.split()
        row = dict(zip(names, v))
        x = np.array([float(row[c]) for c in "xyz"])
        out[int(row["gauge"])] = (float(np.linalg.norm(x - centre)), float(row["arrival"]),
                                  float(row["peak_overpressure"]))
    return out


def gauge_positions(path, centre):
    """{gauge: distance from centre} from a gauge file's header."""
    pos = {}
    for l in header_lines(path):
        m = re.match(r"#\s*gauge\s+(\d+)\s+at\s+radius\s+(\S+)\s*$", l)
        if m:
            pos[int(m.group(1))] = float(m.group(2))
            continue
        m = re.match(r"#\s*gauge\s+(\d+)\s+at\s+(\S+)\s+(\S+)\s+(\S+)\s*$", l)
        if m:
            x = np.array([float(m.group(k)) for k in (2, 3, 4)])
            pos[int(m.group(1))] = float(np.linalg.norm(x - centre))
    return pos


def read_gauges(path, centre, fraction):
    """{gauge: (distance, arrival, peak)} from a gauge file through blast_gauges."""
    t, ps = blast_gauges.read(path)
    pos = gauge_positions(path, centre)
    out = {}
    for g, p in ps.items():
        if g not in pos:
            sys.exit(f"{path}: no `# gauge {g} at ...` header line")
        a = blast_gauges.answers(t, p, fraction)
        out[g] = (pos[g], a["arrival"], a["peak"])
    return out


def default_label(path):
    b = os.path.basename(path)
    for suffix in ("_prerun_gauges.txt", "_blast.txt", "_gauges.txt", ".txt"):
        if b.endswith(suffix):
            return b[: -len(suffix)] + (" (1D)" if suffix == "_prerun_gauges.txt" else "")
    return b


def kb_value(param, r_m, w, f):
    """KB free air at r_m of w kg: the free-air fits (f None) or a surface burst of w / f."""
    try:
        return kb.free_air(param, r_m, w, f)
    except ValueError:
        return float("nan")


def diff(run, ref):
    return 100.0 * (run / ref - 1.0) if ref > 0 and not math.isnan(ref) and not math.isnan(run) else float("nan")


def table(files, labels, a):
    centre = np.array(a.centre, dtype=float)
    fr = (None, a.reflection)
    rows = []
    for path, label in zip(files, labels):
        data = read_blast(path, centre) if is_blast_file(path) else read_gauges(path, centre, a.fraction)
        for g in sorted(data):
            r, arr, peak = data[g]
            r_m = r * TO_M[a.length_unit]
            row = {"run": label, "gauge": g, "R_m": r_m, "Z": r_m / a.mass_kg ** (1 / 3),
                   "arrival_ms": arr * TO_MS[a.time_unit] if peak > 0 else float("nan"),
                   "peak_kPa": peak * TO_KPA[a.pressure_unit]}
            for f in fr:
                row[f"kb_arrival_{tag(f)}"] = kb_value("arrival", r_m, a.mass_kg, f)
                row[f"kb_peak_{tag(f)}"] = kb_value("overpressure", r_m, a.mass_kg, f)
            rows.append(row)
    return rows, fr


def tag(f):
    """The column tag of a KB reference: the free-air fits (None) or a surface burst of W/f."""
    return "free" if f is None else f"F{f:g}"


def print_table(rows, fr):
    f1, f2 = (tag(f) for f in fr)
    cols = ["run", "gauge", "R_m", "Z", "arrival_ms", f"KB_{f1}", "diff%", f"KB_{f2}", "diff%",
            "peak_kPa", f"KB_{f1}", "diff%", f"KB_{f2}", "diff%"]
    w = max([len("run")] + [len(r["run"]) for r in rows])
    print(f"# Kingery-Bulmash: KB_free = the spherical free-air fits (KB 1984), KB_{f2} = a surface burst of "
          f"W/{fr[1]:g} (Swisdak 1994 fits); diff% = 100 (run/KB - 1)")
    print(f"{cols[0]:<{w}} " + " ".join(f"{c:>10}" for c in cols[1:]))
    out = []
    for r in rows:
        vals = [r["gauge"], r["R_m"], r["Z"], r["arrival_ms"],
                r[f"kb_arrival_{f1}"], diff(r["arrival_ms"], r[f"kb_arrival_{f1}"]),
                r[f"kb_arrival_{f2}"], diff(r["arrival_ms"], r[f"kb_arrival_{f2}"]),
                r["peak_kPa"], r[f"kb_peak_{f1}"], diff(r["peak_kPa"], r[f"kb_peak_{f1}"]),
                r[f"kb_peak_{f2}"], diff(r["peak_kPa"], r[f"kb_peak_{f2}"])]
        out.append([r["run"]] + vals)
        print(f"{r['run']:<{w}} {vals[0]:>10d} " + " ".join(
            f"{v:>+10.1f}" if cols[k + 2] == "diff%" else f"{v:>10.4g}" for k, v in enumerate(vals[1:])))
    if any(math.isnan(r[f"kb_{k}_{f}"]) for r in rows for k in ("peak", "arrival") for f in (f1, f2)):
        print("# nan in a KB column: Z outside the fits' range (kingery_bulmash.py)")
    csv_cols = ["run", "gauge", "R_m", "Z", "arrival_ms", f"arrival_KB_{f1}", f"arrival_diff%_{f1}",
                f"arrival_KB_{f2}", f"arrival_diff%_{f2}", "peak_kPa", f"peak_KB_{f1}", f"peak_diff%_{f1}",
                f"peak_KB_{f2}", f"peak_diff%_{f2}"]
    return csv_cols, out


def plot(rows, fr, labels, a):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    zs = np.array([r["Z"] for r in rows if r["Z"] > 0])
    zlo, zhi = zs.min() / 1.4, zs.max() * 1.4
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, param, key, ylab in [(axes[0], "overpressure", "peak_kPa", "peak overpressure [kPa]"),
                                 (axes[1], "arrival", "arrival_ms", "arrival time [ms]")]:
        for f, style, name in zip(fr, ("-", "--"), ("Kingery-Bulmash free air (KB 1984 fits)",
                                                      f"surface burst of W/{fr[1]:g} (Swisdak 1994 fits)")):
            # the free-air Z range the fits cover (with f: through the surface burst of W/f;
            # pulled in by 1e-9: the round trip through f^(1/3) must not leave the range)
            lo, hi = kb.z_range(param, free=f is None)
            s = 1.0 if f is None else f ** (1 / 3)
            lo, hi = lo * (1 + 1e-9) / s, hi * (1 - 1e-9) / s
            z = np.geomspace(max(zlo, lo), min(zhi, hi), 200)
            y = np.array([kb.free_air(param, zz * a.mass_kg ** (1 / 3), a.mass_kg, f) for zz in z])
            ax.plot(z, y, "k" + style, lw=1.4 if f is None else 1.0, label=name)
        markers = "osD^v<>ph*"
        for k, label in enumerate(labels):
            pts = [(r["Z"], r[key]) for r in rows if r["run"] == label and r[key] > 0]
            if pts:
                z, y = np.array(pts).T
                ax.plot(z, y, markers[k % len(markers)], ms=7, mfc="none", mew=1.5, label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("Z = R / W$^{1/3}$ [m/kg$^{1/3}$]")
        ax.set_ylabel(ylab)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"{a.mass_kg:g} kg TNT in free air: runs against Kingery-Bulmash")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", help="<name>_blast.txt or gauge files (<name>_prerun_gauges.txt)")
    ap.add_argument("--mass-kg", type=float, required=True, help="TNT mass of the free-air charge, kg")
    ap.add_argument("--centre", type=float, nargs=3, default=[0.0, 0.0, 0.0], help="charge centre (deck units)")
    ap.add_argument("--length-unit", choices=TO_M, default="mm")
    ap.add_argument("--pressure-unit", choices=TO_KPA, default="GPa")
    ap.add_argument("--time-unit", choices=TO_MS, default="us")
    ap.add_argument("--reflection", type=float, default=1.8,
                    help="also against a surface burst of W/F (default 1.8, UFC 3-340-02)")
    ap.add_argument("--fraction", type=float, default=0.5, help="gauge files: arrival at this fraction of the peak")
    ap.add_argument("--label", action="append", help="one per FILE, in order (default: from the file name)")
    ap.add_argument("--out", default="blast_kb.png", help="PNG to write")
    ap.add_argument("--csv", help="also write the table as CSV")
    a = ap.parse_args(argv)
    if not a.mass_kg > 0 or not a.reflection > 0:
        sys.exit("--mass-kg and --reflection must be positive")
    labels = a.label or [default_label(p) for p in a.files]
    if len(labels) != len(a.files):
        sys.exit(f"{len(labels)} --label for {len(a.files)} files")
    rows, fr = table(a.files, labels, a)
    if not rows:
        sys.exit("no gauges in the files")
    cols, out = print_table(rows, fr)
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols)
            w.writerows(out)
    plot(rows, fr, labels, a)
    print(f"wrote {a.out}: {len(rows)} gauge(s) of {len(a.files)} run(s)")


if __name__ == "__main__":
    main()
