#!/usr/bin/python3
"""Check that a frame of a rescaled run equals the original frame rescaled,
bit for bit (the dimensional-rescaling invariance test; ARCHITECTURE.md §6).

    check_scaling.py ORIG.h5 SCALED.h5 --L 3 --T -2 --M 5

SCALED.h5 comes from the deck of ORIG.h5 with lengths scaled by 2^L, times
by 2^T and masses by 2^M (tools/scale_deck.py). Every dataset of dimension
L^l T^t M^m in ORIG.h5, multiplied by 2^(l L + t T + m M) (exact in binary
floating point), must have the same bits as the dataset in SCALED.h5. Per
dataset the check prints its dimension, the factor, the largest relative
difference max|s a - b| / max|s a|, the number of differing elements and
whether it is bit-identical.

Every dataset must have a known dimension (table DIMENSIONS; per-material
fields by their prefix, MATERIAL_PREFIXES: vf_<material> is dimensionless,
density_<material>, energy_<material>, pressure_<material> as the cell fields): an unknown one is refused, so
a new output field cannot go unchecked. `deck` (the resolved deck text,
which differs by construction) is not compared.
Exit status: 0 all bit-identical, 1 a mismatch, 2 usage, file or
unknown-dataset errors.
"""
import debian_python  # tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("h5py", "numpy")

import argparse
import sys

import h5py
import numpy as np

# dimension exponents (L, T, M)
PRES = (-1, -2, 1)
DIMENSIONS = {
    "x": (1, 0, 0),
    "velocity": (1, -1, 0),
    "node_mass": (0, 0, 1),            # the nodal mass of the kinetic energy
    "density": (-3, 0, 1),
    "pressure": PRES,
    "energy": (2, -2, 0),              # specific internal energy
    "sound_speed": (1, -1, 0),
    "viscosity": PRES,                 # artificial viscosity q, a pressure
    "material": (0, 0, 0),             # material index
    "volume": (3, 0, 0),
    "time": (0, 1, 0),
    "step": (0, 0, 0),
    "totals/mass": (0, 0, 1),
    "totals/momentum": (1, -1, 1),
    "totals/internal_energy": (2, -2, 1),
    "totals/kinetic_energy": (2, -2, 1),
    "totals/initial_energy": (2, -2, 1),
    "totals/boundary_work": (2, -2, 1),
}
NOT_COMPARED = {"deck"}


# per-material fields <prefix><material> (the frames of a multi-material run)
MATERIAL_PREFIXES = {
    "vf_": (0, 0, 0),                  # volume fraction
    "density_": (-3, 0, 1),
    "energy_": (2, -2, 0),             # specific internal energy
    "pressure_": PRES,
}


def dimension(name):
    if name in DIMENSIONS:
        return DIMENSIONS[name]
    for prefix, d in MATERIAL_PREFIXES.items():
        if name.startswith(prefix) and len(name) > len(prefix):
            return d
    return None


def datasets(f):
    names = []
    f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
    return sorted(names)


def dim_text(d):
    parts = [f"{s}^{e}" if e != 1 else s for s, e in zip("LTM", d) if e != 0]
    return " ".join(parts) if parts else "1"


def compare(name, a, b, factor):
    """(ok, max_rel, n_diff, note) of b against factor * a, bitwise."""
    if a.shape != b.shape:
        return False, float("nan"), -1, f"shapes {a.shape} and {b.shape}"
    if a.dtype.kind in "iu":
        if factor != 1.0:
            return False, float("nan"), -1, "an integer dataset with a dimension"
        diff = a != b
        ok = not diff.any()
        return ok, 0.0 if ok else float("inf"), int(diff.sum()), ""
    a = a.astype(np.float64)
    b = b.astype(np.float64)
    s = a * factor
    if not np.array_equal(s / factor, a, equal_nan=True):
        return False, float("nan"), -1, "the scaled reference over- or underflows"
    diff = s.view(np.uint64) != b.view(np.uint64)
    n = int(diff.sum())
    with np.errstate(invalid="ignore", divide="ignore"):
        den = np.max(np.abs(s)) if s.size else 0.0
        num = np.max(np.abs(s - b)) if s.size else 0.0
        rel = num / den if den > 0 else (0.0 if num == 0 else float("inf"))
    return n == 0, float(rel), n, ""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("orig")
    ap.add_argument("scaled")
    ap.add_argument("--L", type=int, default=0, help="lengths were scaled by 2^L")
    ap.add_argument("--T", type=int, default=0, help="times were scaled by 2^T")
    ap.add_argument("--M", type=int, default=0, help="masses were scaled by 2^M")
    args = ap.parse_args(argv)
    try:
        fa = h5py.File(args.orig, "r")
        fb = h5py.File(args.scaled, "r")
    except OSError as e:
        print(f"check_scaling: {e}", file=sys.stderr)
        return 2
    with fa, fb:
        na, nb = datasets(fa), datasets(fb)
        if na != nb:
            print(f"FAIL: the files hold different datasets: only in {args.orig}: "
                  f"{sorted(set(na) - set(nb))}, only in {args.scaled}: {sorted(set(nb) - set(na))}")
            return 1
        unknown = [n for n in na if n not in NOT_COMPARED and dimension(n) is None]
        if unknown:
            print(f"check_scaling: datasets of unknown dimension: {', '.join(unknown)}; add them "
                  f"to DIMENSIONS in {__file__}", file=sys.stderr)
            return 2
        print(f"{args.scaled} against {args.orig} scaled by L = 2^{args.L}, T = 2^{args.T}, "
              f"M = 2^{args.M}")
        print(f"{'dataset':24s} {'dimension':12s} {'factor':>10s} {'max rel diff':>12s} "
              f"{'differ':>8s}  result")
        failed = []
        for n in na:
            if n in NOT_COMPARED:
                continue
            d = dimension(n)
            k = d[0] * args.L + d[1] * args.T + d[2] * args.M
            factor = 2.0 ** k
            ok, rel, ndiff, note = compare(n, fa[n][()], fb[n][()], factor)
            size = fa[n].size
            result = "bit-identical" if ok else "DIFFERENT" + (f" ({note})" if note else "")
            print(f"{n:24s} {dim_text(d):12s} {'2^' + str(k):>10s} {rel:12.3e} "
                  f"{ndiff:>4d}/{size:<4d} {result}")
            if not ok:
                failed.append(n)
        if failed:
            print(f"FAIL: {len(failed)} dataset(s) not bit-identical after scaling: {', '.join(failed)}")
            return 1
        print("PASS: every dataset bit-identical after scaling")
        return 0


if __name__ == "__main__":
    sys.exit(main())
