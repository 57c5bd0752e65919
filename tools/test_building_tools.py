#!/usr/bin/env python3
"""Tests of the tools of the paper's building scene (issue 39) on synthetic
data with known answers:

- track_displacement.py on a tracks file of two particles, one swinging as
  u = 2 sin(2 pi t) (largest +2 at t = 0.25, its first peak there, back to
  0 at t = 1), one drifting to -3 without turning back (no first peak), and
  a third swinging with a ripple of 1 % of its amplitude on the way up (not
  a peak at --drop 0.05);
- body_damage_png.py on a frame of two bodies: body 1 with damage 0, 0.3,
  0.7 and 1 (counts above 0.1, 0.5 and at 1: 3, 2, 1; mirrored in y the
  counts stay those of the body's own particles), body 2 left out, and the
  PNG's darkest colour present (the damaged particle drawn);
- building_deck.py --check: input/building.nml holds the particle groups
  its generator writes.
"""
import os
import re
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def run(args):
    out = subprocess.run([sys.executable] + args, capture_output=True, text=True)
    print(out.stdout, out.stderr)
    return out


def tracks_file(path):
    t = np.linspace(0.0, 1.0, 201)
    u = [2 * np.sin(2 * np.pi * t), -3 * t, np.sin(2 * np.pi * t) + 0.01 * np.sin(40 * np.pi * t) * (t < 0.2)]
    names = ["time"]
    cols = [t]
    for k, uk in enumerate(u, 1):
        names += ["id_%d" % k, "x_%d" % k, "y_%d" % k, "z_%d" % k]
        cols += [np.full_like(t, 10 * k), 5.0 + uk, np.zeros_like(t), np.zeros_like(t)]
    np.savetxt(path, np.stack(cols, axis=1), header="a tracks file\n" + " ".join(names))


def frame_file(path):
    x = np.array([[0.5, 0.5, 0.5], [0.5, 0.5, 1.5], [0.5, 0.5, 2.5], [0.5, 0.5, 3.5], [5.0, 5.0, 5.0]])
    with h5py.File(path, "w") as f:
        f["time"] = 2.0
        f["particles/x"] = x
        f["particles/damage"] = np.array([0.0, 0.3, 0.7, 1.0, 1.0])
        f["particles/body"] = np.array([1, 1, 1, 1, 2], dtype=np.int32)
        f["particles/volume"] = np.ones(5)


def main():
    ok = True
    with tempfile.TemporaryDirectory() as d:
        tracks, frame, png = (os.path.join(d, n) for n in ("t_tracks.txt", "f.h5", "f.png"))
        tracks_file(tracks)
        out = run([os.path.join(HERE, "track_displacement.py"), tracks])
        want = [r"track 1 \(id 10\): largest x displacement \+2 at t = 0.25; first peak \+2 at t = 0.25; "
                r"at t = 1: [-+][0-9.]*e-1[56]",
                r"track 2 \(id 20\): largest x displacement -3 at t = 1; no first peak yet",
                r"track 3 \(id 30\): largest x displacement \+1 at t = 0.25; first peak \+1 at t = 0.25"]
        for w in want:
            hit = re.search(w, out.stdout) is not None
            print("%s: %s" % (w, "ok" if hit else "FAIL"))
            ok = ok and hit
        frame_file(frame)
        for mirror in ([], ["--mirror", "y"]):
            out = run([os.path.join(HERE, "body_damage_png.py"), "--run", "syn", frame, "--body", "1",
                       "--out", png] + mirror)
            hit = out.returncode == 0 and "syn: t = 2, 4 particles, damage > 0.1: 3, > 0.5: 2, = 1: 1" in out.stdout
            print("counts %s: %s" % (mirror, "ok" if hit else "FAIL"))
            ok = ok and hit
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.image import imread
        img = imread(png)[:, :, :3] if os.path.exists(png) else np.zeros((1, 1, 3))
        dark = np.array(plt.get_cmap("inferno_r")(1.0)[:3])
        n = int(np.all(np.abs(img - dark) < 0.02, axis=2).sum())
        print("pixels of damage 1's colour: %d (some expected): %s" % (n, "ok" if n > 0 else "FAIL"))
        ok = ok and n > 0
    deck = os.path.join(HERE, "..", "input", "building.nml")
    out = run([os.path.join(HERE, "building_deck.py"), deck, "--check"])
    print("input/building.nml's groups are its generator's: %s" % ("ok" if out.returncode == 0 else "FAIL"))
    ok = ok and out.returncode == 0
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
