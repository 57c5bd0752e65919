#!/usr/bin/env python3
"""The frame series of a run: one line per frame the XDMF file lists,
`NNNNN  time  step` (time as the exact double, step from the frame file),
with particles also the frame's particle count, `particles N`.

    restart_frames.py OUTDIR NAME

Fails (exit 1) if a listed frame is missing, if its time differs from the
XDMF's, if the particle count the XDMF gives a frame is not the frame
file's (particles leave the grid, so the counts differ between frames), or
if a frame file OUTDIR/NAME_NNNNN.h5 exists that the XDMF does not list (a
frame written and then dropped from the series).
"""
import glob
import os
import re
import sys

import h5py


def main():
    outdir, name = sys.argv[1], sys.argv[2]
    xdmf = open(os.path.join(outdir, name + ".xdmf")).read()
    grids = re.split(r"<Grid Name=\"frame_", xdmf)[1:]
    listed = []
    for g in grids:
        t = re.search(r"<Time Value=\"([^\"]+)\"", g).group(1)
        f = re.search(r"([^\s>]+_(\d{5})\.h5):/", g)
        m = re.search(r'TopologyType="Polyvertex" NumberOfElements="(\d+)"', g)
        listed.append((f.group(1), f.group(2), float(t), int(m.group(1)) if m else 0))
    bad = 0
    for fname, num, t, npart in listed:
        path = os.path.join(outdir, fname)
        if not os.path.exists(path):
            print(f"FAIL: {fname} is listed but missing")
            bad += 1
            continue
        with h5py.File(path, "r") as h:
            tf, step = float(h["time"][()]), int(h["step"][()])
            nfile = h["particles/x"].shape[0] if "particles/x" in h else 0
        if tf != t:
            print(f"FAIL: {fname}: time {tf!r} in the file, {t!r} in the XDMF")
            bad += 1
        if nfile != npart:
            print(f"FAIL: {fname}: {nfile} particles in the file, {npart} in the XDMF")
            bad += 1
        print(f"{num}  {tf!r}  {step}" + (f"  particles {nfile}" if nfile else ""))
    names = {os.path.basename(p) for p in glob.glob(os.path.join(outdir, name + "_[0-9][0-9][0-9][0-9][0-9].h5"))}
    for extra in sorted(names - {f for f, _, _, _ in listed}):
        print(f"FAIL: {extra} exists but the XDMF does not list it")
        bad += 1
    sys.exit(1 if bad else 0)


main()
