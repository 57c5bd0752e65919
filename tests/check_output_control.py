#!/usr/bin/python3
"""Checks of the &output frame controls (fields, particle_fields, precision,
compress); tests/output_control.sh runs them.

    check_output_control.py content DIR NAME
        every frame DIR/NAME_NNNNN.h5 of a run of tests/decks/output_control.nml
        holds exactly the chosen grid and particle fields (plus the
        coordinates, the particles' vertex numbers, time, step, totals and
        the deck), its real arrays float32, its integer arrays int32, every
        array compressed (gzip with shuffle), particles/failed an integer,
        particles/temperature in 'temperature' units; the XDMF series (grid
        and particles) list the
        fields written, with Precision="4" for the reals
    check_output_control.py versus SINGLE_DIR DOUBLE_DIR NAME
        each frame of the single-precision run equals float32() of the
        same frame of the double-precision run, bit for bit, every dataset
        (the integers equal, the scalars time and totals equal doubles)
    check_output_control.py dumps A.h5 B.h5
        two restart dumps hold the same state bit for bit (scalars/, state/),
        every array double or integer, checksummed (Fletcher-32) and
        uncompressed, whatever the frames' settings (but scalars/nframe: a
        split run's first part writes a final frame of its own)
Exit status: 0 pass, 1 fail.
"""
import glob
import os
import re
import sys

import h5py
import numpy as np

# the deck's choice (tests/decks/output_control.nml), with its two materials
GRID = {"x", "velocity", "density", "material", "vf_air", "vf_rht901", "pressure_air", "pressure_rht901"}
PARTICLES = {"x", "vertex", "velocity", "stress", "id", "failed", "temperature", "damage"}
ALWAYS = {"time", "step", "deck", "totals/mass", "totals/momentum", "totals/internal_energy",
          "totals/kinetic_energy", "totals/initial_energy", "totals/boundary_work"}
INTS = {"material", "particles/id", "particles/failed", "particles/vertex"}

problems = []


def bad(msg):
    problems.append(msg)
    print("FAIL:", msg)


def datasets(f):
    out = {}
    f.visititems(lambda n, o: out.__setitem__(n, o) if isinstance(o, h5py.Dataset) else None)
    return out


def frames(d, name):
    paths = sorted(glob.glob(os.path.join(d, f"{name}_[0-9][0-9][0-9][0-9][0-9].h5")))
    if not paths:
        bad(f"no frames {d}/{name}_NNNNN.h5")
    return paths


def content(d, name):
    want = GRID | {"particles/" + p for p in PARTICLES} | ALWAYS
    paths = frames(d, name)
    for path in paths:
        with h5py.File(path, "r") as f:
            ds = datasets(f)
            have = set(ds)
            if have != want:
                bad(f"{path}: datasets {sorted(have - want)} not chosen, {sorted(want - have)} missing")
            for n, o in ds.items():
                if o.shape == () or n == "totals/momentum":
                    continue         # (scalars and the totals: doubles, not compressed)
                kind = "int32" if n in INTS else "float32"
                if o.dtype != np.dtype(kind):
                    bad(f"{path}: {n} is {o.dtype}, expected {kind}")
                if o.compression != "gzip" or not o.shuffle or o.compression_opts != 6:
                    bad(f"{path}: {n} compression {o.compression} {o.compression_opts} shuffle {o.shuffle}, "
                        f"expected gzip 6 with shuffle")
            for n in ("time", "totals/mass"):
                if n in ds and ds[n].dtype != np.float64:
                    bad(f"{path}: {n} is {ds[n].dtype}, expected float64")
            units = f["particles/temperature"].attrs.get("units", b"")
            units = units.decode() if isinstance(units, bytes) else str(units)
            if units != "temperature":
                bad(f"{path}: particles/temperature units '{units}', expected 'temperature'")
            nfailed = int(np.sum(f["particles/failed"][()])) if "particles/failed" in f else -1
        print(f"{os.path.basename(path)}: {len(have)} datasets as chosen, reals float32, gzip 6 + shuffle, "
              f"{nfailed} particles failed")
    if nfailed <= 0:
        bad(f"{paths[-1]}: no failed particle: the failure flags are not exercised")
    # the grid's series and the particles' (<name>_particles.xdmf), together
    xdmf = open(os.path.join(d, name + ".xdmf")).read() + open(os.path.join(d, name + "_particles.xdmf")).read()
    listed = set(re.findall(r'<Attribute Name="([^"]+)"', xdmf)) - {"time"}
    listed = {a for a in listed if not a.startswith("material ")}   # (the legend, field data)
    expect = (GRID - {"x"}) | (PARTICLES - {"x", "vertex"})
    if listed != expect:
        bad(f"XDMF lists {sorted(listed - expect)} not written, misses {sorted(expect - listed)}")
    precisions = set(re.findall(r'NumberType="Float" Precision="(\d)" Format="HDF"', xdmf))
    if precisions != {"4"}:
        bad(f"XDMF float Precision {sorted(precisions)}, expected only 4 (inline field data aside)")
    if not re.search(r'NumberType="Int" Precision="4" Format="HDF">[^<]*particles/failed', xdmf):
        bad("XDMF does not list particles/failed as Int")
    print(f"XDMF: {len(listed)} attributes, the fields written; reals Precision 4; failed Int")


def versus(dsingle, ddouble, name):
    ps, pd = frames(dsingle, name), frames(ddouble, name)
    if [os.path.basename(p) for p in ps] != [os.path.basename(p) for p in pd]:
        bad(f"frame lists differ: {len(ps)} against {len(pd)}")
        return
    nvalues = 0
    for a, b in zip(ps, pd):
        with h5py.File(a, "r") as fs, h5py.File(b, "r") as fd:
            s, d = datasets(fs), datasets(fd)
            if set(s) != set(d):
                bad(f"{a}: datasets differ from {b}")
                continue
            for n in sorted(s):
                if n == "deck":
                    continue
                vs, vd = s[n][()], d[n][()]
                if d[n].dtype == np.float64 and s[n].dtype == np.float32:
                    expect = np.asarray(vd).astype(np.float32)
                else:
                    expect = vd
                    if s[n].dtype != d[n].dtype:
                        bad(f"{a}: {n} is {s[n].dtype} in the single frame, {d[n].dtype} in the double one")
                        continue
                if np.shape(vs) != np.shape(expect) or np.asarray(vs).tobytes() != np.asarray(expect).tobytes():
                    diff = np.max(np.abs(np.asarray(vs, float) - np.asarray(expect, float)))
                    bad(f"{a}: {n} differs from float32 of the double frame (max |difference| {diff:.3e})")
                nvalues += np.size(vs)
    print(f"{len(ps)} frames: every dataset of the single-precision run equals float32 (or the same integers, "
          f"scalars) of the double-precision run, {nvalues} values")


def dumps(a, b):
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        da, db = datasets(fa), datasets(fb)
        # (scalars/nframe, the frame count, is bookkeeping: a split run's
        # first part writes a final frame of its own)
        names = sorted(n for n in set(da) | set(db) if n.startswith(("scalars/", "state/")) and n != "scalars/nframe")
        for n in names:
            if n not in da or n not in db:
                bad(f"{n} only in {'the second' if n not in da else 'the first'} dump")
                continue
            for path, o in ((a, da[n]), (b, db[n])):
                if o.dtype.kind == "f" and o.dtype != np.float64:
                    bad(f"{path}: {n} is {o.dtype}, a dump holds doubles")
                if not o.fletcher32 or o.compression is not None:
                    bad(f"{path}: {n} fletcher32 {o.fletcher32} compression {o.compression}")
            if da[n][()].tobytes() != db[n][()].tobytes() or da[n].dtype != db[n].dtype:
                bad(f"{n} differs between the dumps")
    print(f"dumps {os.path.basename(a)} and {os.path.basename(b)}: {len(names)} datasets identical, doubles and "
          f"integers, Fletcher-32, uncompressed")


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "content":
        content(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 5 and sys.argv[1] == "versus":
        versus(sys.argv[2], sys.argv[3], sys.argv[4])
    elif len(sys.argv) == 4 and sys.argv[1] == "dumps":
        dumps(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
    print("PASS" if not problems else f"FAIL: {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
