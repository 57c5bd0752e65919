#!/usr/bin/env python3
"""Test of tools/fragments_png.py on synthetic frames: a 40 x 8 block of
particles (spacing 1, two layers in z) whose column at x = 20.5 fails in
the second frame, and the corner particle cut off by failing its three
neighbours and moved away (a fragment of one particle, not a main one).
Expected: 2 main fragments, 3 fragments, 19 failed (the printed counts), and a PNG that shows the two
main fragments in the first two colours of the palette."""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True
from test_fragments import write  # noqa: E402


def main():
    g = np.arange(0.5, 40, 1.0)
    xx, yy, zz = np.meshgrid(g, np.arange(0.5, 8, 1.0), [0.5, 1.5], indexing="ij")
    x0 = np.stack([xx.ravel(), yy.ravel(), zz.ravel()], axis=1)
    failed = np.abs(x0[:, 0] - 20.5) < 0.1
    x1 = x0.copy()
    x1[:, 0] += np.where(x0[:, 0] > 20.5, 5.0, 0.0)
    # (the corner particle cut off by failing its three neighbours)
    corner = np.all(x0 == 0.5, axis=1)
    failed |= np.isclose(np.abs(x0 - 0.5).sum(axis=1), 1.0) & np.all(x0 <= 1.5, axis=1)
    x1[corner] = [-20.0, -20.0, 0.5]
    with tempfile.TemporaryDirectory() as d:
        f0, f1, png = (os.path.join(d, n) for n in ("f0.h5", "f1.h5", "f.png"))
        write(f0, 0.0, x0, np.zeros(len(x0), bool))
        write(f1, 1.0, x1, failed)
        out = subprocess.run([sys.executable, os.path.join(HERE, "fragments_png.py"), "--run", "block", f0, f1,
                              "--out", png], capture_output=True, text=True)
        print(out.stdout, out.stderr)
        m = re.search(r"block: t = 1, (\d+) main fragments, (\d+) fragments, (\d+) failed", out.stdout)
        ok = out.returncode == 0 and m is not None and [int(v) for v in m.groups()] == [2, 3, 19]
        print(f"counts {m.groups() if m else None} (expected 2, 3, 19): {'ok' if ok else 'FAIL'}")
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.image import imread
        img = imread(png)[:, :, :3] if os.path.exists(png) else np.zeros((1, 1, 3))
        for k, c in enumerate(plt.get_cmap("tab10").colors[:3]):
            near = np.all(np.abs(img - np.array(c)) < 0.02, axis=2).sum()
            want = near > 0 if k < 2 else near == 0
            print(f"pixels of palette colour {k + 1}: {near} ({'some' if k < 2 else 'none'} expected): "
                  f"{'ok' if want else 'FAIL'}")
            ok = ok and want
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
