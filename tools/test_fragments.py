#!/usr/bin/env python3
"""Test of tools/fragments.py on a synthetic quarter ring: particles on a
0.25 lattice in 30 <= r <= 34 (two layers in z), then the ring expanded
(every radius + 6, thickness kept) with the particles within half a
spacing of the rays at 30 and 60 degrees failed. Expected: 3 fragments,
all main; the two at the symmetry planes flagged, their widths doubled;
first through-crack at the second frame; thickness 4 within a spacing
(lattice columns are cut by the slices); widths pi/6 r_mean (middle) and
2 pi/6 r_mean (doubled) within 2 spacings (the crack takes one spacing,
the + spacing of the measure gives one back). A third frame without the
particles beyond y = 38 (they left the grid): the "left" column counts
them exactly, and the fragments are still 3. With --gaps 2 (fragments by
the gaps between particles in each frame, failed ones included): the
second frame's ring is one piece (its cracks are failed particles in
place); a fourth frame, the three 30-degree sectors of the second turned
apart by 1/40 rad each (about 4 spacings), gives 3 main fragments holding
every particle, thickness 4 within a spacing."""
import os
import re
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def write(path, t, x, failed, ids=None):
    with h5py.File(path, "w") as f:
        f["time"] = t
        f["particles/id"] = np.arange(1, len(x) + 1, dtype=np.int32) if ids is None else ids
        f["particles/x"] = x
        f["particles/failed"] = failed.astype(float)


def main():
    s = 0.25
    g = np.arange(s / 2, 40, s)
    xx, yy, zz = np.meshgrid(g, g, [s / 2, 3 * s / 2], indexing="ij")
    x = np.stack([xx.ravel(), yy.ravel(), zz.ravel()], axis=1)
    r = np.hypot(x[:, 0], x[:, 1])
    x = x[(r >= 30) & (r <= 34)]
    r = np.hypot(x[:, 0], x[:, 1])
    th = np.arctan2(x[:, 1], x[:, 0])
    r1 = r + 6.0
    x1 = np.stack([r1 * np.cos(th), r1 * np.sin(th), x[:, 2]], axis=1)
    failed = np.zeros(len(x), bool)
    for a in (np.pi / 6, np.pi / 3):
        # distance from the ray at angle a
        failed |= np.abs(-np.sin(a) * x[:, 0] + np.cos(a) * x[:, 1]) < s / 2
    with tempfile.TemporaryDirectory() as d:
        f0, f1 = os.path.join(d, "f0.h5"), os.path.join(d, "f1.h5")
        write(f0, 0.0, x, np.zeros(len(x), bool))
        write(f1, 1.0, x1, failed)
        f2 = os.path.join(d, "f2.h5")
        stay = x1[:, 1] <= 38.0
        write(f2, 2.0, x1[stay], failed[stay], np.arange(1, len(x) + 1, dtype=np.int32)[stay])
        out = subprocess.run([sys.executable, os.path.join(HERE, "fragments.py"), f0, f1, f2, "--quarter"],
                             capture_output=True, text=True)
        out1 = subprocess.run([sys.executable, os.path.join(HERE, "fragments.py"), f0, f1, "--quarter"],
                              capture_output=True, text=True)
        # the sectors (by angle) turned apart: sector k by k/40 rad (about
        # 1 mm at r = 40, 4 spacings)
        th1 = np.arctan2(x1[:, 1], x1[:, 0])
        th3 = th1 + np.minimum(th1 // (np.pi / 6), 2) / 40.0
        r3 = np.hypot(x1[:, 0], x1[:, 1])
        f3 = os.path.join(d, "f3.h5")
        write(f3, 3.0, np.stack([r3 * np.cos(th3), r3 * np.sin(th3), x1[:, 2]], axis=1), failed)
        gaps = [subprocess.run([sys.executable, os.path.join(HERE, "fragments.py"), f0, f, "--quarter", "--gaps", "2"],
                               capture_output=True, text=True) for f in (f1, f3)]
    print(out.stdout, out.stderr)
    row2 = re.search(r"^\s+2\s+(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s*$", out.stdout, re.M)
    left_ok = row2 is not None and int(row2.group(2)) == int((~stay).sum()) and int(row2.group(4)) == 3
    out = out1
    print(out.stdout, out.stderr)
    ok = out.returncode == 0
    table = out.stdout.split("main fragments at")[-1]
    rows = re.findall(r"^\s+(\d+)\s+([\d.eE+-]+)\s+([\d.eE+-]+)(\s+sym)?", table, re.M)
    rm = 38.0
    checks = [
        (f"{int((~stay).sum())} left, 3 main fragments in the third frame", left_ok),
        ("3 main fragments", len(rows) == 3),
        ("first through-crack at t = 1", "first through-crack): 1" in out.stdout),
        ("two flagged at the symmetry planes", sum(1 for r in rows if r[3]) == 2),
    ]
    for n, w, h, sym in rows:
        w, h = float(w), float(h)
        want = (2 if sym else 1) * np.pi / 6 * rm
        checks.append((f"width {w:.3f} ~ {want:.3f}", abs(w - want) <= 2 * s * (2 if sym else 1)))
        checks.append((f"thickness {h:.3f} ~ 4", abs(h - 4.0) <= s))
    print(gaps[0].stdout, gaps[0].stderr, gaps[1].stdout, gaps[1].stderr)
    ok = ok and gaps[0].returncode == 0 and gaps[1].returncode == 0
    one = re.search(r"^\s+1\s+\d+\s+\d+\s+(\d+)\s+(\d+)\s*$", gaps[0].stdout, re.M)
    checks.append(("--gaps: the cracked ring in place is one fragment", one is not None and one.groups() == ("1", "1")))
    grows = re.findall(r"^\s+(\d+)\s+([\d.eE+-]+)\s+([\d.eE+-]+)(\s+sym)?", gaps[1].stdout.split("main fragments at")[-1],
                       re.M)
    checks.append(("--gaps: 3 main fragments apart, holding every particle",
                   len(grows) == 3 and sum(int(g[0]) for g in grows) == len(x)))
    checks += [(f"--gaps: thickness {float(g[2]):.3f} ~ 4", abs(float(g[2]) - 4.0) <= s) for g in grows]
    for label, good in checks:
        print(f"  {label:40s} {'ok' if good else 'FAIL'}")
        ok = ok and good
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
