#!/usr/bin/env python3
"""Gas / linear-elastic solid Riemann problem (PARTICLES.md section 4, rung
4) against the exact solution of tools/exact/gas_solid.py, at two
resolutions: a quasi-1D run along x (one cell across), gas cells on the
left, coupled particles filling the cells right of X0 (their cells hold the
virtual fluid, which the check ignores).

    check_particles_gas_solid.py COARSE FINE RHO U P GAMMA RHO_S U_S SXX M X0 \\
        L1P_COARSE L1U_COARSE L1P_FINE L1U_FINE RATIO_MIN

COARSE and FINE are the final frames of the two runs. For each, the L1
errors (per unit cross-section, i.e. integrals over x)

    pressure: sum over gas cells |p_c - <p>_c| dx_c + sum over particles |-sigma_xx,p - p(x_p)| V_p / A
    velocity: sum over gas nodes |u_n - u(x_n)| dx_n + sum over particles |u_p - u(x_p)| V_p / A

(<p>_c the exact cell average, dx_n the gas part of a node's dual length, A
the cross-section) must be below the bounds, and each error must fall by at
least RATIO_MIN from COARSE to FINE. Prints every error and ratio.
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "exact"))
sys.dont_write_bytecode = True
from gas_solid import GasSolidSolution  # noqa: E402


def errors(frame, sol, x0):
    """(L1 pressure, L1 velocity, t, number of gas cells) of one frame; prints
    the gas and solid parts."""
    with h5py.File(frame, "r") as f:
        t = float(f["time"][()])
        xn = f["x"][()]                       # (nk+1, nj+1, ni+1, 3)
        vn = f["velocity"][()]
        pc = f["pressure"][()]                # (nk, nj, ni)
        px = f["particles/x"][()][:, 0]
        pu = f["particles/velocity"][()][:, 0]
        psxx = f["particles/stress"][()][:, 0]
        pvol = f["particles/volume"][()]
        pcell = f["particles/cell"][()]
    nk, nj, ni = pc.shape
    if nj != 1 or nk != 1:
        sys.exit(f"FAIL: {frame} is not one cell across (ni, nj, nk) = {(ni, nj, nk)}")
    edges = xn[..., 0].reshape(-1, ni + 1).mean(axis=0)
    un = vn[..., 0].reshape(-1, ni + 1).mean(axis=0)
    area = np.mean((xn[0, 1, :, 1] - xn[0, 0, :, 1]) * (xn[1, 0, :, 2] - xn[0, 0, :, 2]))
    solid_cells = np.zeros(ni, dtype=bool)
    solid_cells[np.unique(pcell) - 1] = True      # host cells (1-based; i here)
    gas = ~solid_cells
    ngas = int(np.argmin(gas)) if not gas.all() else ni
    if gas[ngas:].any():
        sys.exit(f"FAIL: {frame}: the gas cells are not the first {ngas} cells")
    # gas: cells 0..ngas-1, nodes 0..ngas (the last one is the interface's)
    p_ex, _, _ = sol.cell_average(edges[:ngas + 1], t, x0)
    dx = np.diff(edges[:ngas + 1])
    l1p = np.sum(np.abs(pc.reshape(-1)[:ngas] - p_ex) * dx)
    dual = np.zeros(ngas + 1)
    dual[:-1] += 0.5 * dx
    dual[1:] += 0.5 * dx
    _, u_ex, _ = sol.sample(edges[:ngas + 1], t, x0)
    l1u = np.sum(np.abs(un[:ngas + 1] - u_ex) * dual)
    # solid: the particles, each the length V_p / A
    p_ex, u_ex, _ = sol.sample(px, t, x0)
    length = pvol / area
    sp = np.sum(np.abs(-psxx - p_ex) * length)
    su = np.sum(np.abs(pu - u_ex) * length)
    print(f"  {os.path.basename(frame)}: gas part of L1 pressure {l1p:.3e}, velocity {l1u:.3e};"
          f" solid part {sp:.3e}, {su:.3e}")
    return l1p + sp, l1u + su, t, ngas


def main():
    coarse, fine = sys.argv[1:3]
    rho, u, p, g, rho_s, u_s, sxx, modulus, x0 = (float(v) for v in sys.argv[3:12])
    bounds = [float(v) for v in sys.argv[12:16]]
    ratio_min = float(sys.argv[16])
    sol = GasSolidSolution((rho, u, p, g), (rho_s, u_s, sxx, modulus), gas_side="left")
    print(f"exact: p* = {sol.p_star:.6g}, u* = {sol.u_star:.6g}, gas {'shock' if sol.gas_shock else 'rarefaction'}"
          f" at {sol.gas_head:.4g} t, solid front at {sol.solid_front:.4g} t")
    ok = True
    res = []
    for frame, (bp, bu) in ((coarse, bounds[0:2]), (fine, bounds[2:4])):
        l1p, l1u, t, ngas = errors(frame, sol, x0)
        res.append((l1p, l1u))
        good = l1p <= bp and l1u <= bu
        ok = ok and good
        print(f"{os.path.basename(frame)}: t = {t:.6g}, {ngas} gas cells: L1 pressure {l1p:.4e} (bound {bp:.1e}),"
              f" L1 velocity {l1u:.4e} (bound {bu:.1e})  {'ok' if good else 'FAIL'}")
    for k, name in enumerate(("pressure", "velocity")):
        ratio = res[0][k] / res[1][k]
        good = ratio >= ratio_min
        ok = ok and good
        print(f"L1 {name} coarse / fine = {ratio:.3f} (at least {ratio_min})  {'ok' if good else 'FAIL'}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()
