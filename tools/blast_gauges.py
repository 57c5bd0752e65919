#!/usr/bin/env python3
"""Blast answers from a gauge file: per gauge the arrival time, peak
overpressure, positive-phase duration and positive impulse.

    blast_gauges.py GAUGES.txt [--fraction F] [--ambient P] [--csv OUT]

The definitions are those of the run's own <name>_blast.txt
(modules/io/io_blast.f90), on the same rows, linear between them:
overpressure dp = p - p0 (p0 the first row's pressure, or --ambient);
peak the largest dp (first row that has it), an arrival only if it exceeds
DETECTION = 1e-4 of |p0| (else the shock's exponentially small foot ahead
of a captured front: no arrival, duration or impulse); arrival the first time dp
reaches F times the peak (default 0.5: the middle of a captured shock's
rise); the positive phase from the last dp <= 0 before the arrival to the
first dp <= 0 after the peak (duration counted from the arrival; "ended 0"
when dp stays positive to the last row, duration and impulse then up to it);
positive impulse the trapezoid integral of dp over that phase.
Prints one line per gauge; --csv writes them as CSV.
"""
import argparse
import csv
import sys

import numpy as np

DETECTION = 1.0e-4   # io_blast's blast_detection

def read(path):
    lines = open(path).read().splitlines()
    head = [l for l in lines if l.startswith("#")]
    if not head:
        sys.exit(f"{path}: no header line naming the columns")
    names = head[-1].lstrip("#").split()
    rows = np.array([list(map(float, l.split())) for l in lines if l.strip() and not l.startswith("#")])
    if names[0] != "time" or rows.ndim != 2 or rows.shape[1] != len(names):
        sys.exit(f"{path}: not a gauge file (columns {names[:3]}...)")
    gauges = sorted(int(n.split("_")[1]) for n in names if n.startswith("pressure_"))
    return rows[:, 0], {g: rows[:, names.index(f"pressure_{g}")] for g in gauges}


def crossing(ta, tb, fa, fb):
    return tb if fa == fb else ta + (tb - ta) * fa / (fa - fb)


def answers(t, p, fraction=0.5, ambient=None):
    p0 = p[0] if ambient is None else ambient
    dp = p - p0
    kp = int(np.argmax(dp))
    out = {"ambient": p0, "peak": dp[kp], "peak_time": t[kp], "arrival": float("nan"),
           "duration": float("nan"), "impulse": 0.0, "ended": 0}
    if not dp[kp] > DETECTION * abs(p0):
        return out
    level = fraction * dp[kp]
    ka = int(np.argmax(dp[: kp + 1] >= level))
    out["arrival"] = t[ka] if ka == 0 else crossing(t[ka - 1], t[ka], dp[ka - 1] - level, dp[ka] - level)
    kz, ts = 0, t[0]
    for k in range(ka - 1, -1, -1):
        if dp[k] <= 0:
            ts, kz = crossing(t[k], t[k + 1], dp[k], dp[k + 1]), k + 1
            break
    imp = 0.5 * dp[kz] * (t[kz] - ts) if kz > 0 else 0.0
    te = t[-1]
    for k in range(kz, len(t) - 1):
        if k + 1 > kp and dp[k + 1] <= 0:
            te = crossing(t[k], t[k + 1], dp[k], dp[k + 1])
            imp += 0.5 * dp[k] * (te - t[k])
            out["ended"] = 1
            break
        imp += 0.5 * (dp[k] + dp[k + 1]) * (t[k + 1] - t[k])
    out["impulse"], out["duration"] = imp, te - out["arrival"]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("gauges")
    ap.add_argument("--fraction", type=float, default=0.5, help="arrival at this fraction of the peak (0.5)")
    ap.add_argument("--ambient", type=float, help="ambient pressure (default: each gauge's first row)")
    ap.add_argument("--csv", help="write the answers as CSV")
    a = ap.parse_args()
    if not 0 < a.fraction <= 1:
        sys.exit("--fraction must be in (0, 1]")
    t, ps = read(a.gauges)
    keys = ["ambient", "arrival", "peak", "peak_time", "duration", "impulse", "ended"]
    rows = []
    print("gauge " + " ".join(f"{k:>14}" for k in keys))
    for g, p in ps.items():
        r = answers(t, p, a.fraction, a.ambient)
        rows.append([g] + [r[k] for k in keys])
        print(f"{g:5d} " + " ".join(f"{r[k]:14.6e}" if k != "ended" else f"{r[k]:14d}" for k in keys))
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["gauge"] + keys)
            w.writerows(rows)
        print(f"wrote {a.csv}: {len(rows)} gauges")


if __name__ == "__main__":
    main()
