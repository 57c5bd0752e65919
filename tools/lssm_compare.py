#!/usr/bin/python3
"""Euler-phase cost and accuracy of the rezone modes on the Sedov octant, as an
ensemble: the Euler steps fire on trigger thresholds, so their number, the
cells they remap and the errors move with round-off (at 10^3 and 20^3 by
tens of per cent between builds). One run per mode says little; this runs
each mode on several copies of the deck whose source energy differs in the
ninth digit (physically nothing, numerically a different trigger history)
and reports the mean and range of each figure, and the ratio of the mean
Euler-phase times to that of the first mode.

    lssm_compare.py --exe build/release/lsalepm --n 20 --copies 3 --jobs 2 \\
        --out DIR [--modes lssm:0 smooth:0 lssm:0.1 smooth:0.1]

A mode is MODE:MOVE_MIN (&rezone mode and move_min); the deck is
input/sedov3d_lssm.nml (the paper's settings: triggers side ratio 4 or
cosine 0.7, q = 0.999, Q_min 0.999, N_max 20) with ni = nj = nk = N. The
runs go JOBS at a time with one OpenMP thread each, interleaved across modes
so that every mode shares the machine alike; the Euler-phase time is the
`euler` entry of the log's `timers` line (wall seconds of the Euler steps:
rezone and remap). L1 is tools/profile_plot.py's volume-weighted density
error against the exact solution. Writes DIR/runs/ and DIR/lssm_compare.csv
and prints a markdown table.
"""
import debian_python  # tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("h5py", "matplotlib", "numpy")

import argparse
import concurrent.futures
import csv
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import profile_plot  # noqa: E402

DECK = os.path.join(HERE, "..", "input", "sedov3d_lssm.nml")
ENERGY, GAMMA, RHO0 = 0.851072, 1.4, 1.0


def make_deck(path, outdir, n, mode, move_min, copy):
    with open(DECK) as f:
        text = f.read()
    text = re.sub(r"ni = \d+, nj = \d+, nk = \d+", f"ni = {n}, nj = {n}, nk = {n}", text)
    text = text.replace("mode = 'lssm'", f"mode = '{mode}'")
    # (in the groups, not the header's comments)
    text = re.sub(r"^([^!\n]*smooth_iterations = \d+)", rf"\1, move_min = {move_min}", text, flags=re.M)
    # the ensemble: source energy E0 (1 + copy 1e-9), which moves the shock
    # radius (E^(1/5)) by 2e-10 per copy
    text = text.replace("energy = 0.106384", f"energy = {0.106384 * (1.0 + copy * 1.0e-9):.15e}")
    text = re.sub(r"^&output .*/[ \t]*$", f"&output dir = '{outdir}' /", text, flags=re.M)
    body = "\n".join(line for line in text.splitlines() if not line.lstrip().startswith("!"))
    for what in (f"mode = '{mode}'", f"move_min = {move_min}", f"ni = {n}",
                 "&source position = 0, 0, 0, energy = ",
                 f"&output dir = '{outdir}' /"):
        if what not in body:
            raise SystemExit(f"{DECK}: could not set {what}")
    with open(path, "w") as f:
        f.write(text)


def run_one(exe, out, n, mode, move_min, copy):
    name = f"{mode}_{move_min}_{copy}"
    rundir = os.path.join(out, "runs", name)
    os.makedirs(rundir, exist_ok=True)
    deck = os.path.join(rundir, name + ".nml")
    make_deck(deck, rundir, n, mode, move_min, copy)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with open(os.path.join(rundir, "stdout.txt"), "w") as so:
        rc = subprocess.run([exe, deck], stdout=so, stderr=subprocess.STDOUT, env=env).returncode
    if rc != 0:
        raise SystemExit(f"{name}: lsalepm exited with {rc}")
    log = open(os.path.join(rundir, name + ".log")).read()
    m = re.search(r"timers \[s\]:.*?euler\s+([0-9.]+)", log)
    e = re.search(r"euler steps: (\d+), cells remapped (\d+)", log)
    s = re.search(r"done: t = \S+ after (\d+) steps", log)
    if not (m and e and s):
        raise SystemExit(f"{name}: log lacks the timers / euler steps / done lines")
    frames = sorted(f for f in os.listdir(rundir) if f.endswith(".h5"))
    fr = profile_plot.read_frame(os.path.join(rundir, frames[-1]))
    sol = profile_plot.make_sedov(GAMMA, ENERGY, RHO0)
    l1 = profile_plot.sedov_l1(profile_plot.radial_cells(fr), sol, fr["time"])[0]
    return dict(mode=mode, move_min=move_min, copy=copy, steps=int(s.group(1)), euler_steps=int(e.group(1)),
                cells=int(e.group(2)), euler_s=float(m.group(1)), l1=l1)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--exe", default="build/release/lsalepm")
    p.add_argument("--n", type=int, default=20)
    p.add_argument("--copies", type=int, default=3)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--modes", nargs="+", default=["smooth:0", "lssm:0", "lssm:0.1", "smooth:0.1"])
    p.add_argument("--out", required=True)
    a = p.parse_args(argv)
    exe = os.path.abspath(a.exe)
    modes = [tuple(m.split(":")) for m in a.modes]
    jobs = [(mode, mm, c) for c in range(a.copies) for (mode, mm) in modes]
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        rows = list(pool.map(lambda j: run_one(exe, a.out, a.n, *j), jobs))
    with open(os.path.join(a.out, "lssm_compare.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)

    def rng(vals, fmt):
        return f"{fmt.format(sum(vals) / len(vals))} ({fmt.format(min(vals))}-{fmt.format(max(vals))})"

    base = None
    print(f"Sedov {a.n}^3, {a.copies} copies per mode, {a.jobs} runs at a time, "
          f"1 thread each (mean (min-max))\n")
    print("| mode | move_min | Euler steps | cells remapped | Euler phase [s] | ratio of means | L1 density |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for mode, mm in modes:
        r = [x for x in rows if x["mode"] == mode and x["move_min"] == mm]
        t = sum(x["euler_s"] for x in r) / len(r)
        base = base or t
        print(f"| {mode} | {mm} | {rng([x['euler_steps'] for x in r], '{:.0f}')} | "
              f"{rng([x['cells'] for x in r], '{:.0f}')} | {rng([x['euler_s'] for x in r], '{:.1f}')} | "
              f"{t / base:.3f} | {rng([x['l1'] for x in r], '{:.4f}')} |")


if __name__ == "__main__":
    main()
