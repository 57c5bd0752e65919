#!/usr/bin/env python3
"""Translation check: a ball of one material carried by a uniform flow
through a fixed grid (Euler steps back to the initial grid) against the
exact solution, the same ball moved by u t.

    check_translation.py OUTDIR NAME MATERIAL INDEX --density RHO
                         --centre CX CY CZ --radius R --velocity UX UY UZ
                         --mass-tol M --shape-tol S --centroid-tol C --still-tol V

OUTDIR/NAME_00000.h5 is the initial frame, the highest-numbered
OUTDIR/NAME_NNNNN.h5 the final one, and the newest OUTDIR/NAME_restart_*.h5
(written at the final time: the deck sets dump_dt = t_end) holds the mixed
cells, so the material's mass. MATERIAL is its name (frames hold vf_MATERIAL),
INDEX its number (deck order, from 1), RHO its initial density, and the ball
|x - C| <= R its initial shape on the grid.

Reported and checked:
  mass      |M(t) - M(0)| / M(0) for the material; M(0) = RHO sum vf V of
            the initial frame (the deck builds exactly that), M(t) = the pure
            cells' masses plus its mixed-cell masses in the restart file.
  shape     sum_c |vf_c - vf_exact_c| V_c / V_ball: L1 of the volume
            fractions against the exact translated ball's (sampled n^3 = 24^3
            points in each cell its surface cuts; sampling error ~1e-4),
            relative to the ball's volume. The initial frame's own error
            (the deck's sub-sampled fractions) is printed for comparison.
  centroid  |c(t) - c(0) - u t| / h, c the volume centroid sum vf V x_c /
            sum vf V with cell centres x_c; on the same grid the cell-centre
            approximation is the same for both, so for an exact translation
            by whole cells this is zero.
  still     the largest |u_node - u| of the nodes within 2 cells of the
            ball: the flow around it must stay uniform (round-off).
The final grid must be the initial one (the run ends with an Euler step).
Run with /usr/bin/python3 (Debian numpy and h5py).
"""
import argparse
import glob
import os
import sys

import h5py
import numpy as np

sys.dont_write_bytecode = True


def read_frame(path, material):
    with h5py.File(path, "r") as f:
        return {"x": f["x"][()], "vf": f["vf_" + material][()], "vol": f["volume"][()],
                "t": float(f["time"][()]), "u": f["velocity"][()]}


def cell_centres(x):
    """Mean of the 8 nodes of each cell; x is (nk+1, nj+1, ni+1, 3)."""
    return 0.125 * (x[:-1, :-1, :-1] + x[1:, :-1, :-1] + x[:-1, 1:, :-1] + x[1:, 1:, :-1]
                    + x[:-1, :-1, 1:] + x[1:, :-1, 1:] + x[:-1, 1:, 1:] + x[1:, 1:, 1:])


def exact_fractions(x, c, r, n=24):
    """Volume fraction of the ball |p - c| <= r in each cell of an
    axis-aligned grid: 0 or 1 away from the surface, n^3 midpoint samples in
    the cells the surface cuts."""
    lo = x[:-1, :-1, :-1]
    hi = x[1:, 1:, 1:]
    dmin = np.sqrt(((np.maximum(lo - c, 0) + np.maximum(c - hi, 0)) ** 2).sum(-1))
    dmax = np.sqrt((np.maximum(np.abs(lo - c), np.abs(hi - c)) ** 2).sum(-1))
    vf = np.where(dmax <= r, 1.0, 0.0)
    s = (np.arange(n) + 0.5) / n
    for idx in zip(*np.nonzero((dmin < r) & (dmax > r))):
        a, b = lo[idx], hi[idx]
        p = [a[d] + (b[d] - a[d]) * s - c[d] for d in range(3)]
        d2 = p[0][:, None, None] ** 2 + p[1][None, :, None] ** 2 + p[2][None, None, :] ** 2
        vf[idx] = np.count_nonzero(d2 <= r * r) / n ** 3
    return vf


def material_mass(path, index):
    """Mass of material `index` in a restart file: pure cells and mixed slots."""
    with h5py.File(path, "r") as f:
        s = f["state"]
        t = float(f["scalars/time"][()])
        mass = s["mass"][()][s["material"][()] == index].sum()
        mass += s["mixed_mass"][()][s["mixed_material"][()] == index].sum()
    return mass, t


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outdir")
    ap.add_argument("name")
    ap.add_argument("material")
    ap.add_argument("index", type=int)
    ap.add_argument("--density", type=float, required=True)
    ap.add_argument("--centre", type=float, nargs=3, required=True)
    ap.add_argument("--radius", type=float, required=True)
    ap.add_argument("--velocity", type=float, nargs=3, required=True)
    ap.add_argument("--mass-tol", type=float, required=True)
    ap.add_argument("--shape-tol", type=float, required=True)
    ap.add_argument("--centroid-tol", type=float, required=True)
    ap.add_argument("--still-tol", type=float, required=True)
    a = ap.parse_args()

    base = os.path.join(a.outdir, a.name)
    frames = sorted(glob.glob(base + "_[0-9][0-9][0-9][0-9][0-9].h5"))
    restarts = sorted(glob.glob(base + "_restart_*.h5"))
    if len(frames) < 2 or not restarts:
        print(f"FAIL: need {base}_00000.h5, a later frame and a restart file")
        return 1
    f0 = read_frame(frames[0], a.material)
    f1 = read_frame(frames[-1], a.material)
    if not np.array_equal(f0["x"], f1["x"]):
        print("FAIL: the final grid is not the initial grid (no Euler step at the end?)")
        return 1
    vel = np.array(a.velocity)
    shift = vel * (f1["t"] - f0["t"])
    x = f0["x"]
    h = np.max(x[1:, 1:, 1:] - x[:-1, :-1, :-1])
    xc = cell_centres(x)

    m0 = a.density * np.sum(f0["vf"] * f0["vol"])
    m1, t_restart = material_mass(restarts[-1], a.index)
    if t_restart != f1["t"]:
        print(f"FAIL: the restart {restarts[-1]} is at t = {t_restart}, the last frame at {f1['t']}")
        return 1
    mass_err = abs(m1 - m0) / m0

    c0 = np.array(a.centre)
    exact0 = exact_fractions(x, c0, a.radius)
    exact1 = exact_fractions(x, c0 + shift, a.radius)
    vball = np.sum(exact1 * f1["vol"])
    l1_init = np.sum(np.abs(f0["vf"] - exact0) * f0["vol"]) / np.sum(exact0 * f0["vol"])
    l1 = np.sum(np.abs(f1["vf"] - exact1) * f1["vol"]) / vball

    def centroid(fr):
        w = fr["vf"] * fr["vol"]
        return (w[..., None] * xc).reshape(-1, 3).sum(0) / w.sum()
    dc = (centroid(f1) - centroid(f0) - shift) / h
    cen_err = np.linalg.norm(dc)

    near = np.linalg.norm(f1["x"] - (c0 + shift), axis=-1) <= a.radius + 2 * h
    still = np.max(np.abs(f1["u"][near] - vel))

    print(f"t = {f1['t']:.6g}: the ball moved {np.linalg.norm(shift) / h:.2f} cells")
    print(f"mass of {a.material}: relative change {mass_err:.3e} (tolerance {a.mass_tol:.1e})")
    print(f"shape: L1 volume-fraction error / ball volume {l1:.4e} (initial frame, sub-sampled: "
          f"{l1_init:.3e}); tolerance {a.shape_tol:.1e}")
    print(f"centroid: displacement error / cell size {cen_err:.3e} (x, y, z: {dc[0]:.2e}, {dc[1]:.2e}, "
          f"{dc[2]:.2e}); tolerance {a.centroid_tol:.1e}")
    print(f"largest velocity deviation within 2 cells of the ball {still:.3e}; tolerance {a.still_tol:.1e}")
    ok = True
    for bad, msg in ((not mass_err <= a.mass_tol, "the material's mass is not conserved"),
                     (not l1 <= a.shape_tol, "shape error above tolerance"),
                     (not cen_err <= a.centroid_tol, "the ball's centroid is not where u t puts it"),
                     (not still <= a.still_tol, "the flow around the ball is not uniform")):
        if bad:
            print("FAIL: " + msg)
            ok = False
    if ok:
        print("PASS check_translation")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
