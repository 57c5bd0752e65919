#!/usr/bin/python3
"""Error against wall time: run lsalepm at several resolutions, compare the
final frame with the exact solution, and tabulate/plot accuracy versus cost.

    speed_error.py --exe build/release/lsalepm --case sod|sedov \\
                   --n 100 200 400 800 --threads 1 --out DIR

For each N the script writes a deck DIR/runs/<case>_N.nml, runs it with
OMP_NUM_THREADS=--threads (output in DIR/runs/<case>_N/), measures the wall
time of the whole process, reads the throughput and step count from the log
line `throughput: R cell-cycles/s over S steps`, and computes the L1 density
error of the last frame.  It writes

    DIR/<case>_speed_error.csv   N, cells, steps, wall_s, cell_cycles_per_s, L1, order
    DIR/<case>_speed_error.png   L1 against wall time, log-log, points labelled with N

and prints the same table in markdown on stdout.

Cases and error definitions
---------------------------
sod    Deck: tests/decks/sod_x100.nml with ni = N and the y, z thickness 1/N
       (Sod's problem (1, 0, 1) | (0.125, 0, 0.1), gamma 1.4, x0 = 0.5,
       t = 0.2).  Error: L1 = sum_i |rho_i - <rho>_i| dx_i, where dx_i is the
       cell's current length along x (from the node positions) and <rho>_i the
       exact Riemann density (tools/exact/riemann.py) averaged over that cell
       (midpoint rule, 200 sub-intervals) -- the definition of
       tests/check_sod.f90.
sedov  Deck: input/sedov3d.nml (octant, source energy E8 = 0.106384 at the
       origin corner, gamma 1.4, rho0 = 1, t = 1) with ni = nj = nk = N and
       frame_dt removed, so only the first and last frame are written.
       Exact solution: the spherical Sedov-Taylor blast
       (tools/exact/sedov.py) with the full-sphere energy E = 8 x E8 and the
       deck's gamma and ambient density.  Error: the volume-weighted mean
           L1 = sum_{i in S} V_i |rho_i - rho_exact(r_i)| / sum_{i in S} V_i,
       where r_i is the radius of the cell centroid (mean of its 8 nodes),
       V_i the cell volume of the frame, and S the cells with
       r_i < 1.2 R_shock(t).  rho_exact is evaluated at the centroid (not
       cell-averaged), so the figure includes the point-sampling error at the
       shock.
The observed order between consecutive rows is
log(L1_prev / L1) / log(N / N_prev), i.e. with respect to the cell size.

Run with /usr/bin/python3 (Debian numpy, h5py, matplotlib, Agg backend).
"""

import debian_python  # tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("h5py", "matplotlib", "numpy")

import argparse
import csv
import glob
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

sys.dont_write_bytecode = True  # leave no __pycache__ in the source tree
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import profile_plot as pp  # noqa: E402  (frame readers and error norms)

SOD_TEMPLATE = os.path.join(ROOT, "tests", "decks", "sod_x100.nml")
SEDOV_TEMPLATE = os.path.join(ROOT, "input", "sedov3d.nml")
NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"


# --------------------------------------------------------------------- decks
def _set_output(line, outdir):
    """Point the &output group at outdir (absolute) and drop frame_dt and the
    gauges (not needed here, and the Sod slab, 1/N thick, would leave the
    template's gauge outside the box)."""
    line = re.sub(r"\bframe_dt\s*=\s*" + NUM + r"\s*,?\s*", "", line, flags=re.I)
    line = re.sub(r"\bgauge_dt\s*=\s*" + NUM + r"\s*,?\s*", "", line, flags=re.I)
    line = re.sub(r"\bgauge\s*=\s*" + NUM + r"(\s*,\s*" + NUM + r")*\s*,?\s*", "", line, flags=re.I)
    if re.search(r"\bdir\s*=", line, flags=re.I):
        line = re.sub(r"\bdir\s*=\s*(['\"]).*?\1", f"dir = '{outdir}'", line, flags=re.I)
    else:
        line = re.sub(r"&output\b", f"&output dir = '{outdir}',", line, flags=re.I)
    line = re.sub(r",\s*/", " /", line)
    return line


def _edit_deck(template, outdir, title, edit_grid):
    """The template deck with a new title, the &grid line passed through
    edit_grid, and &output pointed at outdir (added if missing)."""
    out = []
    has_output = False
    for line in open(template).read().splitlines():
        s = line.lstrip().lower()
        if s.startswith("&run"):
            line = re.sub(r"\btitle\s*=\s*(['\"]).*?\1", f"title = '{title}'", line, flags=re.I)
        elif s.startswith("&grid"):
            line = edit_grid(line)
        elif s.startswith("&output"):
            line = _set_output(line, outdir)
            has_output = True
        out.append(line)
    if not has_output:
        out.append(f"&output dir = '{outdir}' /")
    return "\n".join(out) + "\n"


def sod_deck(template, n, outdir):
    h = 1.0 / n

    def grid(line):
        line = re.sub(r"\bni\s*=\s*\d+", f"ni = {n}", line, flags=re.I)
        m = re.search(r"\bxmax\s*=\s*(" + NUM + r")\s*,\s*" + NUM + r"\s*,\s*" + NUM, line, flags=re.I)
        if not m:
            raise SystemExit(f"{template}: cannot find xmax = X, Y, Z in the &grid line")
        return line[:m.start()] + f"xmax = {m.group(1)}, {h:.17g}, {h:.17g}" + line[m.end():]

    return _edit_deck(template, outdir, f"Sod along x, {n} x 1 x 1", grid)


def sedov_deck(template, n, outdir):
    def grid(line):
        for v in ("ni", "nj", "nk"):
            line = re.sub(rf"\b{v}\s*=\s*\d+", f"{v} = {n}", line, flags=re.I)
        return line

    return _edit_deck(template, outdir, f"Sedov 3D octant, {n}^3", grid)


def deck_value(text, group, var):
    """First number of `var` in the first line of `group` (simple decks)."""
    for line in text.splitlines():
        if line.lstrip().lower().startswith("&" + group):
            m = re.search(rf"\b{var}\s*=\s*({NUM})", line.split("!")[0], flags=re.I)
            if m:
                return float(m.group(1).replace("d", "e").replace("D", "e"))
    return None


# --------------------------------------------------------------------- runs
def run_case(exe, deck_path, outdir, name, threads):
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    # stale frames from an earlier run would be mistaken for this one
    for f in glob.glob(os.path.join(outdir, f"{name}_*.h5")):
        os.remove(f)
    t0 = time.perf_counter()
    proc = subprocess.run([exe, deck_path], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - t0
    with open(os.path.join(os.path.dirname(deck_path), f"{name}.stdout"), "w") as f:
        f.write(proc.stdout)
    if proc.returncode != 0:
        tail = "\n".join(proc.stdout.splitlines()[-15:])
        raise SystemExit(f"{exe} {deck_path} failed with status {proc.returncode}:\n{tail}")
    log = os.path.join(outdir, f"{name}.log")
    text = open(log).read()
    m = re.search(r"throughput:\s*(" + NUM + r")\s*cell-cycles/s\s+over\s+(\d+)\s+steps", text)
    if not m:
        raise SystemExit(f"{log}: no 'throughput: ... cell-cycles/s over N steps' line")
    frames = sorted(glob.glob(os.path.join(outdir, f"{name}_[0-9][0-9][0-9][0-9][0-9].h5")))
    if not frames:
        raise SystemExit(f"{outdir}: no frames {name}_NNNNN.h5")
    return dict(wall=wall, rate=float(m.group(1)), steps=int(m.group(2)), frame=frames[-1],
                nframes=len(frames))


def sod_error(frame):
    from exact.riemann import RiemannSolution
    fr = pp.read_frame(frame)
    prof = pp.line_profile(fr, "x")
    rs = RiemannSolution(*pp.SOD_LEFT, 1.4, *pp.SOD_RIGHT, 1.4)
    return pp.riemann_l1(prof, rs, fr["time"], 0.5), fr


def sedov_error(frame, energy, gamma, rho0):
    fr = pp.read_frame(frame)
    sol = pp.make_sedov(gamma, energy, rho0)
    l1, _ = pp.sedov_l1(pp.radial_cells(fr), sol, fr["time"])
    return l1, fr


# --------------------------------------------------------------------- output
def write_outputs(case, rows, outdir, threads):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    csv_path = os.path.join(outdir, f"{case}_speed_error.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["N", "cells", "steps", "wall_s", "cell_cycles_per_s", "L1", "order"])
        for r in rows:
            w.writerow([r["N"], r["cells"], r["steps"], f"{r['wall']:.4f}", f"{r['rate']:.4e}",
                        f"{r['L1']:.6e}", "" if r["order"] is None else f"{r['order']:.3f}"])

    fig, ax = plt.subplots(figsize=(6.5, 5))
    wall = [r["wall"] for r in rows]
    l1 = [r["L1"] for r in rows]
    ax.loglog(wall, l1, "o-", color="C0")
    for r in rows:
        ax.annotate(f"N = {r['N']}", (r["wall"], r["L1"]), textcoords="offset points",
                    xytext=(6, 4), fontsize=9)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("L1 density error" + (" (sum |rho - <rho>| dx)" if case == "sod"
                                         else " (volume-weighted mean, r < 1.2 R_shock)"))
    ax.set_title(f"{case}: L1 density error against wall time ({threads} thread{'s' if threads != 1 else ''})")
    ax.grid(True, which="both", alpha=0.3)
    # a little room for the labels
    ax.set_xlim(min(wall) / 1.5, max(wall) * 3.0)
    ax.set_ylim(min(l1) / 1.4, max(l1) * 1.4)
    fig.tight_layout()
    png_path = os.path.join(outdir, f"{case}_speed_error.png")
    fig.savefig(png_path, dpi=110)
    plt.close(fig)
    return csv_path, png_path


def markdown(case, rows, threads):
    lines = [f"### {case}: L1 density error against wall time, OMP_NUM_THREADS={threads}", "",
             "| N | cells | steps | wall [s] | cell-cycles/s | L1 | order |",
             "|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        order = "" if r["order"] is None else f"{r['order']:.2f}"
        lines.append(f"| {r['N']} | {r['cells']} | {r['steps']} | {r['wall']:.3f} | "
                     f"{r['rate']:.3e} | {r['L1']:.4e} | {order} |")
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "release", "lsalepm"),
                   help="lsalepm executable (default: build/release/lsalepm of this checkout)")
    p.add_argument("--case", choices=("sod", "sedov"), required=True)
    p.add_argument("--n", type=int, nargs="+", required=True, help="resolutions (cells per direction)")
    p.add_argument("--threads", type=int, default=1, help="OMP_NUM_THREADS for the runs (default 1)")
    p.add_argument("--out", required=True, help="output directory (decks and runs go to OUT/runs)")
    p.add_argument("--deck", help="template deck (default: tests/decks/sod_x100.nml or input/sedov3d.nml)")
    p.add_argument("--energy", type=float,
                   help="sedov: full-sphere energy (default: 8 x the template's &source energy)")
    a = p.parse_args(argv)

    exe = os.path.abspath(a.exe)
    if not os.access(exe, os.X_OK):
        p.error(f"{exe} is not an executable (build it with `make release`)")
    if any(n < 1 for n in a.n):
        p.error("--n values must be >= 1")
    out = os.path.abspath(a.out)
    runs = os.path.join(out, "runs")
    os.makedirs(runs, exist_ok=True)
    template = os.path.abspath(a.deck or (SOD_TEMPLATE if a.case == "sod" else SEDOV_TEMPLATE))
    ttext = open(template).read()

    if a.case == "sedov":
        gamma = deck_value(ttext, "material", "gamma") or 1.4
        rho0 = deck_value(ttext, "region", "density") or 1.0
        if a.energy is not None:
            energy = a.energy
        else:
            e8 = deck_value(ttext, "source", "energy")
            if e8 is None:
                p.error(f"{template}: no &source energy; give --energy")
            energy = 8.0 * e8

    rows = []
    for n in sorted(set(a.n)):
        name = f"{a.case}_{n}"
        rundir = os.path.join(runs, name)
        deck_path = os.path.join(runs, name + ".nml")
        deck = (sod_deck if a.case == "sod" else sedov_deck)(template, n, rundir)
        with open(deck_path, "w") as f:
            f.write(deck)
        res = run_case(exe, deck_path, rundir, name, a.threads)
        if a.case == "sod":
            l1, fr = sod_error(res["frame"])
        else:
            l1, fr = sedov_error(res["frame"], energy, gamma, rho0)
        cells = int(np.prod(fr["density"].shape))
        order = None
        if rows and rows[-1]["L1"] > 0.0 and l1 > 0.0:
            order = math.log(rows[-1]["L1"] / l1) / math.log(n / rows[-1]["N"])
        rows.append(dict(N=n, cells=cells, steps=res["steps"], wall=res["wall"], rate=res["rate"],
                         L1=l1, order=order, t=fr["time"]))
        print(f"{name}: {cells} cells, {res['steps']} steps to t = {fr['time']:.6g}, "
              f"wall {res['wall']:.3f} s, L1 {l1:.4e}", file=sys.stderr)

    csv_path, png_path = write_outputs(a.case, rows, out, a.threads)
    print(markdown(a.case, rows, a.threads))
    print(f"\nwrote {csv_path} and {png_path}", file=sys.stderr)


if __name__ == "__main__":
    main()
