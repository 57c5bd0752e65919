#!/usr/bin/env python3
"""Test of tools/fragments.py --csv (every fragment's particles, mass,
centre of mass, velocity and size) on synthetic frames whose answers are
known, and, given FRAME0 FRAME of a real run, on those.

    test_fragments_csv.py [FRAME0 FRAME]

Synthetic (spacing 0.5, bonds within 1.1 spacings at t = 0):
- A: body 1, a 3 x 3 x 2 lattice, masses 1 + k/10, velocities (k, 2k, -k)
  for particle k: one fragment of 18 particles;
- B: body 1, a 4 x 2 x 1 lattice 3 away from A and one more particle
  bonded at its end, mass 3, that one failed: one fragment of 8;
- C: body 2, a 2 x 1 x 1 lattice touching A (one spacing away): a
  fragment of its own (bodies never join).
At t = 1 every particle has moved by its velocity. Expected: with --body 1
two rows, A then B (heavier first), their particle counts, masses, centres
of mass and mass-averaged velocities computed here from the same arrays
(to 1e-12 relative: the same sums in another order), bounding boxes (the
spans plus one spacing, to 1e-12) and principal extents (sorted, at least
one spacing; B, a rectangle moved rigidly, has its box's, to 1e-9);
without --body three rows, C with body 2 and 2 particles.
Real frames (a run's first and last frame): the fragments' particles and
masses add up to the unfailed particles present in FRAME and their mass,
and each fragment's mass-averaged velocity and centre of mass lie within
the range of its particles' (exactly as computed from the frame).
"""
import csv
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
fails = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        fails.append(what)


def lattice(nx, ny, nz, s, origin):
    g = np.stack(np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij"), axis=-1)
    return g.reshape(-1, 3) * s + np.asarray(origin, float)


def write(path, t, x, v, m, body, failed):
    with h5py.File(path, "w") as f:
        f["time"] = t
        f["particles/id"] = np.arange(1, len(x) + 1, dtype=np.int32)
        f["particles/x"] = x
        f["particles/velocity"] = v
        f["particles/mass"] = m
        f["particles/body"] = body.astype(np.int32)
        f["particles/failed"] = failed.astype(float)


def run(args):
    out = subprocess.run([sys.executable, os.path.join(HERE, "fragments.py")] + args,
                         capture_output=True, text=True)
    print(out.stdout.strip())
    if out.returncode != 0:
        print(out.stderr)
    return out.returncode


def read_csv(path):
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def close(a, b, rel=1e-12):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return bool(np.all(np.abs(a - b) <= rel * np.maximum(1.0, np.abs(b))))


def synthetic(d):
    s = 0.5
    xa = lattice(3, 3, 2, s, (0, 0, 0))
    xb = lattice(4, 2, 1, s, (3 + 1.0, 0, 0))     # 3 spacings + beyond A's 1.0 extent
    xb = np.concatenate([xb, [[4.0 + 4 * s, 0.0, 0.0]]])  # and one more at its end, which fails
    xc = lattice(2, 1, 1, s, (0, 1.0 + s, 0))     # one spacing above A's top row
    x0 = np.concatenate([xa, xb, xc])
    na, nb, nc = len(xa), len(xb), len(xc)
    k = np.arange(len(x0), dtype=float)
    v = np.stack([k, 2 * k, -k], axis=1)
    v[na:na + nb] = (0.25, -1.0, 0.5)             # B moves rigidly
    m = np.concatenate([1 + k[:na] / 10, np.full(nb, 3.0), np.full(nc, 0.5)])
    body = np.concatenate([np.ones(na + nb), np.full(nc, 2)])
    failed = np.zeros(len(x0), bool)
    failed[na + nb - 1] = True                    # B's extra particle
    x1 = x0 + v
    f0, f1, out = os.path.join(d, "f0.h5"), os.path.join(d, "f1.h5"), os.path.join(d, "frag.csv")
    write(f0, 0.0, x0, v, m, body, np.zeros(len(x0), bool))
    write(f1, 1.0, x1, v, m, body, failed)
    check(run([f0, f1, "--csv", out, "--body", "1", "--no-ring"]) == 0, "fragments.py --body 1 --csv runs")
    rows = read_csv(out)
    check(len(rows) == 2, f"--body 1: {len(rows)} fragments, expected 2 (A, B)")
    want = []
    for sel in (np.arange(na), np.arange(na, na + nb - 1)):
        mm, xx, vv = m[sel], x1[sel], v[sel]
        want.append((len(sel), mm.sum(), (mm[:, None] * xx).sum(0) / mm.sum(), (mm[:, None] * vv).sum(0) / mm.sum(),
                     xx.max(0) - xx.min(0) + s))
    for r, (n, mt, com, vel, box), name in zip(rows, want, "AB"):
        check(r["particles"] == n and r["body"] == 1, f"{name}: {r['particles']:.0f} particles of body "
              f"{r['body']:.0f}, expected {n} of body 1")
        check(close(r["mass"], mt), f"{name}: mass {r['mass']!r}, expected {mt!r}")
        check(close([r["cx"], r["cy"], r["cz"]], com), f"{name}: centre of mass {com}")
        check(close([r["vx"], r["vy"], r["vz"]], vel), f"{name}: velocity {vel}")
        check(close([r["box_x"], r["box_y"], r["box_z"]], box), f"{name}: bounding box {box}")
        ax = [r["axis_1"], r["axis_2"], r["axis_3"]]
        check(ax[0] >= ax[1] >= ax[2] >= s, f"{name}: principal extents {ax} sorted, at least a spacing")
    rb = rows[1]
    check(close([rb["axis_1"], rb["axis_2"], rb["axis_3"]], sorted(want[1][4], reverse=True), 1e-9),
          "B (rigid, along the axes): principal extents are its box's")
    check(run([f0, f1, "--csv", out, "--no-ring"]) == 0, "fragments.py --csv (all bodies) runs")
    rows = read_csv(out)
    check(len(rows) == 3 and any(r["body"] == 2 and r["particles"] == nc for r in rows),
          f"all bodies: {len(rows)} fragments, C of body 2 with {nc} particles on its own")


def real(frame0, frame, d):
    out = os.path.join(d, "real.csv")
    check(run([frame0, frame, "--csv", out, "--no-ring"]) == 0, f"fragments.py on {os.path.basename(frame)}")
    rows = read_csv(out)
    with h5py.File(frame, "r") as f:
        m = f["particles/mass"][()]
        failed = f["particles/failed"][()] > 0.5 if "particles/failed" in f else np.zeros(len(m), bool)
        v = f["particles/velocity"][()]
    alive = ~failed
    check(sum(r["particles"] for r in rows) == alive.sum(),
          f"{len(rows)} fragments of {sum(r['particles'] for r in rows):.0f} particles, "
          f"the frame's {int(alive.sum())} unfailed")
    check(close(sum(r["mass"] for r in rows), m[alive].sum(), 1e-12), "their masses add up to the frame's")
    vlo, vhi = v[alive].min(0), v[alive].max(0)
    check(all(np.all(np.array([r["vx"], r["vy"], r["vz"]]) >= vlo - 1e-12 * np.abs(vlo).max()) and
              np.all(np.array([r["vx"], r["vy"], r["vz"]]) <= vhi + 1e-12 * np.abs(vhi).max()) for r in rows),
          "each velocity within the particles' range")


def main():
    with tempfile.TemporaryDirectory() as d:
        synthetic(d)
        if len(sys.argv) == 3:
            real(sys.argv[1], sys.argv[2], d)
    print("FAIL" if fails else "PASS")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
