#!/usr/bin/python3
"""Speed against error for the TNT octant in each mode: the stability
matrix's TNT sphere in air (hardcases/tnt_sphere.nml: a 10 mm constant-volume
TNT charge, octant of 50 mm, gauges at 20, 30 and 40 mm on the x axis and on
the diagonal) run in 3D in each Euler-phase mode at several resolutions, its
blast answers at the gauges against the converged 1D spherical run of the same
deck (&prerun with t_end <= its time: the 1D run alone, on the same
materials).

    tnt_modes.py --exe build/release/lsalepm --n 16 32 --out DIR
                 [--modes lagrange ale euler euler_quarter euler_hybrid lssm] [--threads 2]
                 [--zone 0.0125] [--timeout 1800]

Modes: the rezone groups of tools/hardcases.py (lagrange: no Euler steps;
ale: global smoothing on the paper's triggers; euler: back to the fixed grid
every step, by swept faces through mixed cells too; lssm: the paper's LSSM;
euler_quarter: euler with `swept_max = 0.25`, the steps that move a node
past a quarter cell hybrid, the default before 0.5), euler_hybrid (euler with
`swept_mixed = .false.`: mixed cells and the cells next to another material
intersected in hybrid steps) and euler_intersect (euler_hybrid with
`swept_hybrid = .false.`: a step with a cell the swept faces cannot take
wholly by intersection). The reference is the 1D run with zones of
--zone mm (0.0125: 800 zones per charge radius; from 0.05 mm its peaks
move by 0.15 and 0.3 % at 20 and 40 mm, 3.3 % at 30 mm).

Per run: wall time (the whole process), steps, Euler steps, and the mean
over the six gauges of |peak / peak_1D - 1| and |arrival / arrival_1D - 1|
(arrival and peak overpressure as the run's own <name>_blast.txt defines
them), the axis and diagonal gauges also apart. Writes DIR/tnt_modes.csv and
prints the table in markdown.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from hardcases import REZONE  # noqa: E402

MODES = dict(REZONE)
# euler with the swept faces only through pure cells amid their own
# material (`swept_mixed` off) and every step that has a cell they cannot
# take remapped whole by intersection (`swept_hybrid` off: the path before
# both)
MODES["euler_intersect"] = dict(REZONE["euler"], swept_hybrid=".false.", swept_mixed=".false.")
# euler with mixed cells and the cells next to another material intersected
# in hybrid steps (`swept_mixed` off: the default before it)
MODES["euler_hybrid"] = dict(REZONE["euler"], swept_mixed=".false.")


def deck(template, name, outdir, n=None, rezone=None, prerun=None):
    """The template with the grid at n^3, the given &rezone (dict) or
    &prerun (text) added, and output to outdir under name."""
    out = []
    for line in open(template).read().splitlines():
        s = line.lstrip().lower()
        if s.startswith("&grid") and n is not None:
            for v in ("ni", "nj", "nk"):
                line = re.sub(rf"\b{v}\s*=\s*\d+", f"{v} = {n}", line, flags=re.I)
        elif s.startswith("&output"):
            line = re.sub(r"dir\s*=\s*'[^']*'", f"dir = '{outdir}', name = '{name}'", line, flags=re.I)
        out.append(line)
    if rezone:
        out.append("&rezone " + ", ".join(f"{k} = {v}" for k, v in rezone.items()) + " /")
    if prerun:
        out.append(f"&prerun {prerun} /")
    return "\n".join(out) + "\n"


def run(exe, text, rundir, name, threads, timeout):
    os.makedirs(rundir, exist_ok=True)
    path = os.path.join(rundir, name + ".nml")
    with open(path, "w") as f:
        f.write(text)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.time()
    try:
        p = subprocess.run([exe, path], cwd=rundir, env=env, capture_output=True, text=True, timeout=timeout)
        status = "ok" if p.returncode == 0 else f"exit {p.returncode}"
        log = p.stdout + p.stderr
    except subprocess.TimeoutExpired as e:
        status = "timeout"
        log = (e.stdout or b"").decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
    return status, time.time() - t0, log


def reference(exe, template, rundir, zone, threads, timeout):
    """Per gauge (arrival, peak overpressure) of the 1D run alone."""
    m = re.search(r"t_end\s*=\s*([0-9.eEdD+-]+)", open(template).read())
    text = deck(template, "tnt_1d", rundir, prerun=f"time = {m.group(1)}, zone_width = {zone}")
    status, _, log = run(exe, text, rundir, "tnt_1d", threads, timeout)
    ref = {}
    for g, a, p in re.findall(r"^prerun gauge (\d+) \(radius [^)]*\): arrival\s+(\S+), peak overpressure\s+(\S+),",
                              log, flags=re.M):
        ref[int(g)] = (float(a), float(p))
    if status != "ok" or not ref:
        sys.exit(f"the 1D reference run failed ({status}):\n{log[-2000:]}")
    return ref


def blast(path):
    """Per gauge (arrival, peak overpressure) from a <name>_blast.txt."""
    res = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        v = line.split()
        res[int(v[0])] = (float(v[5]), float(v[6]))
    return res


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--exe", default=os.path.join(ROOT, "build", "release", "lsalepm"))
    p.add_argument("--deck", default=os.path.join(ROOT, "hardcases", "tnt_sphere.nml"))
    p.add_argument("--n", type=int, nargs="+", default=[16, 32])
    p.add_argument("--modes", nargs="+", default=["lagrange", "ale", "euler", "euler_quarter", "euler_hybrid", "lssm"],
                   choices=sorted(MODES))
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--zone", type=float, default=0.0125, help="the 1D reference's zone width (deck units)")
    p.add_argument("--timeout", type=float, default=1800.0, help="seconds per run")
    p.add_argument("--out", required=True)
    a = p.parse_args(argv)
    rundir = os.path.abspath(os.path.join(a.out, "tnt_modes"))
    ref = reference(os.path.abspath(a.exe), a.deck, rundir, a.zone, a.threads, a.timeout)
    gauges = sorted(ref)
    half = len(gauges) // 2
    rows = []
    for n in a.n:
        for mode in a.modes:
            name = f"tnt_{n}_{mode}"
            status, wall, log = run(os.path.abspath(a.exe), deck(a.deck, name, rundir, n, MODES[mode]), rundir,
                                    name, a.threads, a.timeout)
            m = re.search(r"^done: t = \S+ after (\d+) steps", log, flags=re.M)
            steps = int(m.group(1)) if m else 0
            m = re.search(r"^FATAL \[rank \d+, step (\d+)\].* at t =\s*([0-9.Ee+-]+)", log, flags=re.M)
            if m:
                steps = int(m.group(1))
                status += f", failed at t = {float(m.group(2)):.3g}"
            neuler = len(re.findall(r"^euler \d+ at step", log, flags=re.M))
            nswept = len(re.findall(r"cells remapped by swept faces", log))
            row = dict(n=n, mode=mode, status=status, wall_s=round(wall, 1), steps=steps, euler_steps=neuler,
                       swept_steps=nswept)
            bpath = os.path.join(rundir, name + "_blast.txt")
            if status == "ok" and os.path.exists(bpath):
                b = blast(bpath)
                dp = [abs(b[g][1] / ref[g][1] - 1.0) for g in gauges]
                da = [abs(b[g][0] / ref[g][0] - 1.0) for g in gauges]
                row.update(peak_err=sum(dp) / len(dp), arrival_err=sum(da) / len(da),
                           peak_err_axis=sum(dp[:half]) / half, peak_err_diag=sum(dp[half:]) / (len(dp) - half))
            rows.append(row)
            print(f"{name}: {status}, {wall:.1f} s", file=sys.stderr, flush=True)
    keys = ["n", "mode", "status", "wall_s", "steps", "euler_steps", "swept_steps", "peak_err", "arrival_err",
            "peak_err_axis", "peak_err_diag"]
    with open(os.path.join(a.out, "tnt_modes.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    print("1D reference (arrival us, peak overpressure GPa): " +
          ", ".join(f"g{g} {ref[g][0]:.3f} {ref[g][1]:.4g}" for g in gauges))
    print("| N | mode | status | wall [s] | steps | Euler steps (swept) | peak error | arrival error | "
          "peak error axis / diagonal |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        err = "-"
        if "peak_err" in r:
            err = (f"{100 * r['peak_err']:.1f} % | {100 * r['arrival_err']:.1f} % | "
                   f"{100 * r['peak_err_axis']:.1f} / {100 * r['peak_err_diag']:.1f} %")
        else:
            err = "- | - | -"
        print(f"| {r['n']}^3 | {r['mode']} | {r['status']} | {r['wall_s']} | {r['steps']} | "
              f"{r['euler_steps']} ({r['swept_steps']}) | {err} |")


if __name__ == "__main__":
    main()
