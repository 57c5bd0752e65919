#!/usr/bin/env python3
"""Paper Sect. 7.4, Table 2: the rotating projectile with LSSM against
global smoothing, for domain lengths n x the projectile's.

    projectile_compare.py EXE OUTDIR [--n 4,6,8] [--t-end T] [--modes lssm,smooth]
    projectile_compare.py EXE OUTDIR --deck input/projectiles_nine.nml [--t-end T]

For each n, writes the deck input/projectile_rotating.nml with the domain
[-n/2, n/2] x [-3.5, 3.5] (cells of 0.025 kept), runs it with each &rezone
mode (1 OpenMP thread, one run at a time) and prints a table: Euler steps,
cells remapped per Euler step, the Euler phase's wall time, the ratio of
LSSM's Euler time to global smoothing's (same machine, same sitting), and
the projectile's angular momentum about the z axis at the end against the
start (sum over particles of m (x v_y - y v_x)). With --deck, that deck is
run as it is (its &rezone group must be the 2D deck's LSSM line), the
domain not scaled and no angular momentum printed (the nine-projectile
scene of Table 3). Timings are ratios within
one sitting; the machine's load changes absolute times. Run with
/usr/bin/python3 (h5py).
"""
import argparse
import glob
import os
import re
import subprocess
import sys

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DECK = os.path.join(ROOT, "input", "projectile_rotating.nml")


def deck_for(deck, n, mode, t_end, out):
    text = open(deck).read()
    if n is not None:
        half = n / 2.0
        ni = int(round(n / 0.025))
        text = re.sub(r"&grid ni = \d+", f"&grid ni = {ni}", text)
        text = re.sub(r"xmin = [-\d.]+, -3.5", f"xmin = {-half}, -3.5", text)
        text = re.sub(r"xmax = [-\d.]+, 3.5", f"xmax = {half}, 3.5", text)
    text = re.sub(r"t_end = [\d.]+", f"t_end = {t_end}", text)
    if mode == "smooth":
        text = text.replace("mode = 'lssm', smooth_target = 'cube',", "mode = 'smooth',")
    text = re.sub(r"dir = '[^']*'", f"dir = '{out}'", text)
    return text


def angular_momentum(path):
    with h5py.File(path, "r") as f:
        x, v, m = f["particles/x"][()], f["particles/velocity"][()], f["particles/mass"][()]
    return float(np.sum(m * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0])))


def run(exe, outdir, deck, n, mode, t_end):
    name = f"p{n if n is not None else 'deck'}_{mode}"
    work = os.path.join(outdir, name)
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, name + ".nml")
    open(path, "w").write(deck_for(deck, n, mode, t_end, os.path.join(work, "out")))
    env = dict(os.environ, OMP_NUM_THREADS="1")
    log = subprocess.run([exe, path], capture_output=True, text=True, env=env).stdout
    if "done: t =" not in log:
        return {"n": n, "mode": mode, "failed": log.strip().splitlines()[-3:]}
    euler_s = float(re.search(r"euler\s+([\d.]+)\s+output", log).group(1))
    m = re.search(r"euler steps: (\d+), cells remapped (\d+)", log)
    steps, cells = int(m.group(1)), int(m.group(2))
    dl = float("nan")
    if n is not None:
        frames = sorted(glob.glob(os.path.join(work, "out", "*.h5")))
        dl = angular_momentum(frames[-1]) / angular_momentum(frames[0]) - 1.0
    return {"n": n, "mode": mode, "euler_steps": steps, "cells_per_step": cells / max(steps, 1),
            "euler_s": euler_s, "dL": dl}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("outdir")
    ap.add_argument("--n", default="4,6,8")
    ap.add_argument("--t-end", type=float, default=0.5)
    ap.add_argument("--modes", default="lssm,smooth")
    ap.add_argument("--deck", default=None)
    a = ap.parse_args()
    deck = os.path.abspath(a.deck) if a.deck else DECK
    sizes = [None] if a.deck else [int(v) for v in a.n.split(",")]
    rows = []
    print(f"| n | mode | Euler steps | cells remapped / Euler step | Euler phase s | LSSM / smooth | L(t)/L(0) - 1 |")
    print("|---|---|---|---|---|---|---|")
    for n in sizes:
        for mode in a.modes.split(","):
            r = run(os.path.abspath(a.exe), os.path.abspath(a.outdir), deck, n, mode, a.t_end)
            rows.append(r)
            if "failed" in r:
                print(f"| {n} | {mode} | failed: {' / '.join(r['failed'])} | | | | |")
                continue
            ratio = ""
            lssm = [q for q in rows if q["n"] == n and q["mode"] == "lssm" and "failed" not in q]
            if mode == "smooth" and lssm:
                ratio = f"{lssm[0]['euler_s'] / r['euler_s']:.3f}"
            dl = "" if n is None else f"{r['dL']:+.2e}"
            print(f"| {n if n is not None else '-'} | {mode} | {r['euler_steps']} | {r['cells_per_step']:.0f} | "
                  f"{r['euler_s']:.1f} | {ratio} | {dl} |", flush=True)
    sys.exit(1 if any("failed" in r for r in rows) else 0)


main()
