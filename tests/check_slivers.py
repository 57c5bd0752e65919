#!/usr/bin/env python3
"""Asserts that a run whose every Euler step took the swept-face path left
no sliver: in every frame after the first, no cell holds a material at a
volume fraction in (0, vf_min) unless it held it at exactly that fraction in
the first frame (a cell no step changed keeps the scene's fractions).

usage: check_slivers.py <output prefix> <vf_min> <material> [<material> ...]
(the frames <prefix>_NNNNN.h5 with datasets vf_<material>)"""
import glob
import sys

import h5py
import numpy as np


def main(argv):
    prefix, vf_min, mats = argv[1], float(argv[2]), argv[3:]
    frames = sorted(glob.glob(prefix + "_[0-9][0-9][0-9][0-9][0-9].h5"))
    if len(frames) < 2:
        sys.exit(f"expected at least two frames of {prefix}, found {len(frames)}")
    with h5py.File(frames[0], "r") as f:
        first = {m: f["vf_" + m][()] for m in mats}
    bad = 0
    for path in frames[1:]:
        with h5py.File(path, "r") as f:
            for m in mats:
                vf = f["vf_" + m][()]
                sliver = (vf > 0.0) & (vf < vf_min) & (vf != first[m])
                n = int(np.count_nonzero(sliver))
                if n:
                    print(f"{path}: {n} cells hold {m} below {vf_min:g} (smallest {vf[sliver].min():.3e})")
                    bad += n
    print(f"{len(frames) - 1} frames, {len(mats)} materials: {bad} sliver cells")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
