#!/usr/bin/env python3
"""Blast answers at gauges (modules/io/io_blast.f90, tools/blast_gauges.py).

    check_blast.py TOOL WORKDIR [RUN_PREFIX]

1. A synthetic gauge file of Friedlander waves, dp = Ps (1 - s/td)
   exp(-b s/td) for s = t - ta >= 0 (rows every dt = 1e-3): the tool must
   give the peak Ps (the first row after ta samples it within Ps b dt/td),
   the arrival within one row of ta, the positive duration td within one
   row, and the impulse Ps td (1/b - (1 - e^-b)/b^2) within Ps dt (the
   half row the jump's first trapezoid misses, plus O(dt^2)); a wave that
   is still positive at the end must say "ended 0". A history without
   overpressure gives peak 0 and no arrival, and so does one whose largest
   overpressure is the foot a captured shock runs ahead of itself (1e-9 of
   the ambient pressure, under the detection level of 1e-4: io_blast).
2. With RUN_PREFIX (OUT/NAME of a run with gauges): the run's own
   NAME_blast.txt (written by the Fortran at the end of the run) equals the
   tool's answers on NAME_gauges.txt to 1e-12 relative: two implementations
   of the same definitions.
"""
import math
import os
import subprocess
import sys

import numpy as np

tool, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
bad = 0


def check(ok, what):
    global bad
    bad += not ok
    print(("ok   " if ok else "FAIL ") + what)


dt = 1e-3
t = np.arange(0, 2.0 + dt / 2, dt)
waves = [(1.0, 2.0, 1.0 + 0.4 * dt, 0.5, 1.5), (0.1, 0.3, 0.25 + 0.7 * dt, 0.8, 0.6),
         (1.0, 5.0, 1.7 + 0.5 * dt, 0.5, 1.0), (1.0, 0.0, 0.0, 1.0, 1.0),
         (1.0, 1e-9, 1.5, 1.0, 1.0)]   # (p0, Ps, ta, td, b)
cols, names = [t], ["time"]
for g, (p0, ps, ta, td, b) in enumerate(waves, 1):
    s = t - ta
    dp = np.where(s >= 0, ps * (1 - s / td) * np.exp(-b * s / td), 0.0)
    cols += [np.zeros_like(t), np.ones_like(t), p0 + dp]
    names += [f"cell_{g}", f"density_{g}", f"pressure_{g}"]
path = os.path.join(work, "friedlander_gauges.txt")
with open(path, "w") as f:
    f.write("# synthetic Friedlander waves\n# " + " ".join(names) + "\n")
    for row in np.array(cols).T:
        f.write(" ".join(f"{v:.17e}" for v in row) + "\n")
out = subprocess.run([sys.executable, tool, path, "--csv", os.path.join(work, "friedlander.csv")],
                     capture_output=True, text=True, check=True).stdout
rows = {int(l.split()[0]): [float(v) for v in l.split()[1:]] for l in out.splitlines()[1:] if l.split()[0].isdigit()}
for g, (p0, ps, ta, td, b) in enumerate(waves, 1):
    amb, arr, peak, tpk, dur, imp, ended = rows[g]
    if ps < 1e-4 * p0:
        check(abs(peak - ps) <= 1e-12 and math.isnan(arr) and imp == 0,
              f"gauge {g}: no arrival for an overpressure of {ps:g}: peak {peak:g}, arrival {arr}, impulse {imp}")
        continue
    check(abs(peak - ps) <= ps * b * dt / td, f"gauge {g}: peak {peak:.6f} against {ps} (tolerance {ps * b * dt / td:.1e})")
    check(abs(arr - ta) <= dt, f"gauge {g}: arrival {arr:.6f} against {ta:.6f} (tolerance {dt})")
    if ta + td < t[-1]:
        exact = ps * td * (1 / b - (1 - math.exp(-b)) / b ** 2)
        check(ended == 1 and abs(dur - td) <= dt, f"gauge {g}: duration {dur:.6f} against {td} (tolerance {dt})")
        check(abs(imp - exact) <= ps * dt, f"gauge {g}: impulse {imp:.6e} against {exact:.6e} (tolerance {ps * dt:.1e})")
    else:
        check(ended == 0, f"gauge {g}: still positive at the end: ended {ended}")
if len(sys.argv) > 3:
    prefix = sys.argv[3]
    csv_path = os.path.join(work, "run_blast.csv")
    subprocess.run([sys.executable, tool, prefix + "_gauges.txt", "--csv", csv_path], capture_output=True,
                   check=True)
    lines = open(csv_path).read().splitlines()[1:]
    tool_rows = {int(l.split(",")[0]): [float(v) for v in l.split(",")[1:]] for l in lines}
    run_rows = {int(l.split()[0]): [float(v) for v in l.split()[1:]] for l in open(prefix + "_blast.txt")
                if not l.startswith("#")}
    check(sorted(run_rows) == sorted(tool_rows) and len(run_rows) > 0, f"the run's blast file has gauges {sorted(run_rows)}")
    for g in run_rows:
        x, y, z, amb, arr, peak, tpk, dur, imp, ended = run_rows[g]
        want = dict(zip(["ambient", "arrival", "peak", "peak_time", "duration", "impulse", "ended"], tool_rows[g]))
        got = dict(ambient=amb, arrival=arr, peak=peak, peak_time=tpk, duration=dur, impulse=imp, ended=ended)
        # (no arrival: the tool's arrival and duration are NaN, the run's 0)
        ok = all(got[k] == 0 if math.isnan(want[k]) else abs(got[k] - want[k]) <= 1e-12 * max(abs(want[k]), 1e-300)
                 for k in want)
        check(ok, f"run gauge {g}: the run's answers {[f'{got[k]:.6e}' for k in want]} are the tool's")
sys.exit(1 if bad else 0)
