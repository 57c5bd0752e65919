#!/usr/bin/python3
"""Compare two hydrocode frames (HDF5) field by field.

    compare_frames.py RUN.h5 REF.h5 --exact
        every compared dataset must be bit-for-bit identical, in the same
        type (the default fields, and every particles/ dataset when the
        frames have particles); a default field that neither frame holds
        (&output fields chose others) is skipped and listed as absent, one
        that only one holds is a difference
    compare_frames.py RUN.h5 REF.h5 --tolerances TOL.txt
        per field: max relative difference  max|a-b| / max|b|  and
        L1 relative difference  sum|a-b| / sum|b|  must not exceed the
        field's two tolerances
    compare_frames.py REF.h5 --self-test --tolerances TOL.txt
        test of the tester: the reference passes against itself, and each
        field perturbed by ten times its tolerance is reported as a failure

A tolerance file has one line per field: `name  max_rel  l1_rel  # why`.
Fields are HDF5 dataset paths (density, velocity, totals/kinetic_energy, ...).
Exit status: 0 pass, 1 fail, 2 usage or file errors.
"""
import debian_python  # tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("h5py", "numpy")

import argparse
import sys

import h5py
import numpy as np

DEFAULT_FIELDS = ["x", "velocity", "density", "pressure", "energy", "sound_speed", "max_pressure",
                  "totals/mass", "totals/internal_energy", "totals/kinetic_energy",
                  "time", "step"]


def read_tolerances(path):
    tol = {}
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            name, max_rel, l1_rel = line.split()
            tol[name] = (float(max_rel), float(l1_rel))
    if not tol:
        raise ValueError(f"{path}: no tolerances")
    return tol


def particle_fields(path):
    """The datasets under particles/ of a frame (none without particles)."""
    with h5py.File(path, "r") as f:
        if "particles" not in f:
            return set()
        return {"particles/" + k for k in f["particles"]}


def load(path, names):
    with h5py.File(path, "r") as f:
        missing = [n for n in names if n not in f]
        if missing:
            raise KeyError(f"{path}: missing datasets {missing}")
        return {n: np.asarray(f[n][()], dtype=float) for n in names}


def load_raw(path, names):
    """The datasets `names` as stored (their own dtype), None where absent."""
    with h5py.File(path, "r") as f:
        return {n: (f[n][()] if n in f else None) for n in names}


def identical(a, b):
    """Same presence, shape, dtype and bytes."""
    if a is None or b is None:
        return a is None and b is None
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def differences(a, b):
    if a.shape != b.shape:
        return np.inf, np.inf
    d = np.abs(a - b)
    scale_max = np.max(np.abs(b)) if b.size else 0.0
    scale_l1 = np.sum(np.abs(b))
    max_rel = np.max(d) / scale_max if scale_max > 0 else np.max(d)
    l1_rel = np.sum(d) / scale_l1 if scale_l1 > 0 else np.sum(d)
    return float(max_rel), float(l1_rel)


def compare(run, ref, tol):
    ok = True
    print(f"{'field':28s} {'max_rel':>11s} {'tol':>9s} {'l1_rel':>11s} {'tol':>9s}  result")
    for name, (tmax, tl1) in tol.items():
        mx, l1 = differences(run[name], ref[name])
        good = mx <= tmax and l1 <= tl1
        ok &= good
        print(f"{name:28s} {mx:11.3e} {tmax:9.1e} {l1:11.3e} {tl1:9.1e}  {'pass' if good else 'FAIL'}")
    return ok


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run")
    p.add_argument("ref", nargs="?")
    p.add_argument("--tolerances")
    p.add_argument("--exact", action="store_true")
    p.add_argument("--self-test", action="store_true")
    a = p.parse_args()
    try:
        if a.exact:
            if a.ref is None:
                p.error("--exact needs RUN and REF")
            # the particles' datasets too, when either frame has particles
            # (a frame with them and one without differ)
            pr, pf = particle_fields(a.run), particle_fields(a.ref)
            if pr != pf:
                print(f"particle datasets differ: {sorted(pr)} against {sorted(pf)}")
                print("FAIL: frames differ")
                return 1
            fields = DEFAULT_FIELDS + sorted(pr)
            run, ref = load_raw(a.run, fields), load_raw(a.ref, fields)
            bad = [n for n in fields if not identical(run[n], ref[n])]
            absent = [n for n in fields if run[n] is None and ref[n] is None]
            if len(absent) == len(fields):
                print("FAIL: the frames hold none of the compared fields")
                return 1
            for n in fields:
                what = "absent in both" if n in absent else ("identical" if n not in bad else "DIFFERENT")
                if n in bad and (run[n] is None) != (ref[n] is None):
                    what = "DIFFERENT (only in " + (a.ref if run[n] is None else a.run) + ")"
                print(f"{n:28s} {what}")
            print("PASS: bit-for-bit identical" if not bad else "FAIL: frames differ")
            return 0 if not bad else 1
        if not a.tolerances:
            p.error("give --exact or --tolerances")
        tol = read_tolerances(a.tolerances)
        if a.self_test:
            ref = load(a.run, list(tol))
            if not compare(ref, ref, tol):
                print("FAIL: the reference does not pass against itself")
                return 1
            missed = []
            for name, (tmax, tl1) in tol.items():
                bumped = {k: v.copy() for k, v in ref.items()}
                v = bumped[name].reshape(-1)
                scale = max(np.max(np.abs(v)), 1e-300)
                # ten times beyond the looser of the two bounds (at least a
                # relative 1e-9, so that a zero tolerance is probed too)
                v[v.size // 2] += max(10.0 * max(tmax, tl1 * v.size), 1e-9) * scale
                print(f"-- perturbing {name}")
                if compare(bumped, ref, tol):
                    missed.append(name)
            if missed:
                print(f"FAIL: perturbations not detected in {missed}")
                return 1
            print("PASS: every perturbation beyond tolerance was detected")
            return 0
        run, ref = load(a.run, list(tol)), load(a.ref, list(tol))
        ok = compare(run, ref, tol)
        print("PASS" if ok else "FAIL: differences beyond tolerance")
        return 0 if ok else 1
    except (OSError, KeyError, ValueError) as e:
        print(f"ERROR: {e}")
        return 2


if __name__ == "__main__":
    sys.exit(main())
