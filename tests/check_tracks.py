#!/usr/bin/env python3
"""Checks a tracked-particle file against a frame written at the same time:

    check_tracks.py TRACKS.txt FRAME.h5

- the header names the columns: time, then per track k id_k and the
  particle's fields (io output order, see src/driver_output.f90);
- the last row's time equals the frame's time, and for each tracked id the
  position, velocity, stress (frame order xx, xy, xz, yy, yz, zz), pressure
  -trace/3, von Mises stress and specific energy equal the frame's values of
  the particle with that id. The file prints 17 significant digits, which
  read back to the same double, so x, v, stress and e must agree exactly
  (tolerance 0); pressure and von Mises are recomputed here from the frame's
  stress (tolerance 4 eps of the stress scale: a few roundings);
- the ids are distinct from 0, found in the frame.
Exit status 0 pass, 1 fail.
"""
import sys

import h5py
import numpy as np

tracks, frame = sys.argv[1], sys.argv[2]
eps = np.finfo(float).eps
fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


header = [ln for ln in open(tracks) if ln.startswith("#")]
names = header[-1].split()[1:]
rows = np.loadtxt(tracks, comments="#", ndmin=2)
check(rows.shape[1] == len(names), f"{rows.shape[1]} columns, {len(names)} named")
col = {n: i for i, n in enumerate(names)}
ntrack = sum(1 for n in names if n.startswith("id_"))
check(ntrack > 0, f"{ntrack} tracked particles")
f = h5py.File(frame, "r")
t = float(np.ravel(f["time"][()])[0])
p = {k: f["particles/" + k][()] for k in ("x", "velocity", "stress", "energy", "id")}
last = rows[-1]
check(last[0] == t, f"last row time {last[0]!r} == frame time {t!r} (exact)")
check(np.all(np.diff(rows[:, 0]) > 0), f"{len(rows)} rows, times increasing")
where = {int(i): q for q, i in enumerate(p["id"])}
voigt_from_frame = [0, 3, 5, 4, 2, 1]      # frame xx xy xz yy yz zz -> Voigt xx yy zz yz xz xy
for k in range(1, ntrack + 1):
    pid = int(last[col[f"id_{k}"]])
    check(pid in where, f"track {k}: id {pid} is a particle of the frame")
    if pid not in where:
        continue
    q = where[pid]
    got = lambda names_: np.array([last[col[f"{n}_{k}"]] for n in names_])
    x = got(["x", "y", "z"])
    check(np.array_equal(x, p["x"][q]), f"track {k} (id {pid}): position {x} == frame {p['x'][q]} (exact)")
    v = got(["velocity_x", "velocity_y", "velocity_z"])
    check(np.array_equal(v, p["velocity"][q]), f"track {k}: velocity {v} == frame (exact)")
    s = got(["stress_xx", "stress_yy", "stress_zz", "stress_yz", "stress_xz", "stress_xy"])
    sf = p["stress"][q][voigt_from_frame]
    check(np.array_equal(s, sf), f"track {k}: stress {s} == frame (exact)")
    e = last[col[f"energy_{k}"]]
    check(e == p["energy"][q], f"track {k}: energy {e!r} == frame {p['energy'][q]!r} (exact)")
    pr = -sf[:3].sum() / 3
    dev = sf[:3] + pr
    vm = np.sqrt(1.5 * (np.sum(dev**2) + 2 * np.sum(sf[3:] ** 2)))
    tol = 4 * eps * max(np.abs(sf).max(), 1e-300)
    check(abs(last[col[f"pressure_{k}"]] - pr) <= tol, f"track {k}: pressure {last[col[f'pressure_{k}']]!r} "
          f"vs -trace/3 {pr!r} (tol {tol:.1e})")
    check(abs(last[col[f"von_mises_{k}"]] - vm) <= tol, f"track {k}: von Mises {last[col[f'von_mises_{k}']]!r} "
          f"vs {vm!r} (tol {tol:.1e})")
ids = [int(last[col[f"id_{k}"]]) for k in range(1, ntrack + 1)]
check(all(np.all(rows[:, col[f"id_{k}"]] == ids[k - 1]) for k in range(1, ntrack + 1)),
      f"ids {ids} the same in every row")
print("FAIL" if fails else "PASS")
sys.exit(1 if fails else 0)
