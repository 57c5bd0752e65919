#!/usr/bin/env python3
"""Every material stays admissible in every frame of a run: where its volume
fraction is positive its density is > 0 and its specific internal energy and
pressure are >= the floors given (0 for the ideal gases and the explosive
products of the decks that use this; the exact solution never goes below).

    check_admissible.py FRAME_PREFIX E_MIN P_MIN MAT [MAT ...]

FRAME_PREFIX_NNNNN.h5 are the frames; MAT the material names (the frames'
per-material fields density_MAT, energy_MAT, pressure_MAT, vf_MAT; a
one-material scene's frames have only the cell fields density, energy and
pressure, which then stand for its one material). Prints the smallest value
of each and fails if any is below its floor.
"""
import glob
import sys

import h5py
import numpy as np

prefix, e_min, p_min, mats = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4:]
frames = sorted(glob.glob(prefix + "_[0-9][0-9][0-9][0-9][0-9].h5"))
if not frames:
    sys.exit(f"FAIL: no frames {prefix}_NNNNN.h5")
ok = True
for m in mats:
    lo = {"density": np.inf, "energy": np.inf, "pressure": np.inf}
    for fn in frames:
        with h5py.File(fn, "r") as f:
            one = "vf_" + m not in f and len(mats) == 1
            sel = np.ones(f["density"].shape, bool) if one else f["vf_" + m][()] > 0.0
            for q in lo:
                if sel.any():
                    lo[q] = min(lo[q], float(np.min(f[q if one else q + "_" + m][()][sel])))
    for q, floor, strict in (("density", 0.0, True), ("energy", e_min, False), ("pressure", p_min, False)):
        bad = not (lo[q] > floor if strict else lo[q] >= floor)
        ok = ok and not bad
        print(f"{m}: smallest {q} over {len(frames)} frames {lo[q]:.6e}, floor {floor:g}"
              f"{' (strict)' if strict else ''}: {'FAIL' if bad else 'ok'}")
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
