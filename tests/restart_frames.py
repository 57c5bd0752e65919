#!/usr/bin/env python3
"""The frame series of a run: one line per frame the XDMF file lists,
`NNNNN  time  step` (time as the exact double, step from the frame file),
with particles also the frame's particle count, `particles N` (from the
particles' own series NAME_particles.xdmf, whose frames must have the grid
series' times and files).

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
    # the particles' own series (runs with particles): frame by frame the same
    # times, each frame's count (a frame without particles lists no points)
    ppath = os.path.join(outdir, name + "_particles.xdmf")
    pgrids = re.split(r"<Grid Name=\"frame_", open(ppath).read())[1:] if os.path.exists(ppath) else None
    bad = 0
    if pgrids is not None and len(pgrids) != len(grids):
        print(f"FAIL: {len(grids)} frames in {name}.xdmf, {len(pgrids)} in {name}_particles.xdmf")
        bad += 1
    listed = []
    for k, g in enumerate(grids):
        t = re.search(r"<Time Value=\"([^\"]+)\"", g).group(1)
        f = re.search(r"([^\s>]+_(\d{5})\.h5):/", g)
        m = None
        if pgrids is not None and k < len(pgrids):
            p = pgrids[k]
            tp = re.search(r"<Time Value=\"([^\"]+)\"", p).group(1)
            if tp != t:
                print(f"FAIL: frame {k}: time {tp} in the particles' series, {t} in the grid's")
                bad += 1
            m = re.search(r'TopologyType="Polyvertex" NumberOfElements="(\d+)"', p)
            fp = re.search(r"([^\s>]+_(\d{5})\.h5):/", p)
            if m and fp.group(1) != f.group(1):
                print(f"FAIL: frame {k}: {fp.group(1)} in the particles' series, {f.group(1)} in the grid's")
                bad += 1
        listed.append((f.group(1), f.group(2), float(t), int(m.group(1)) if m else 0))
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
