#!/usr/bin/python3
"""Plot a lsalepm frame against an exact solution (PNG).

--case is required: it names the exact solution to overlay (a frame does not
say which problem it holds).

Sod / Riemann problems (a quasi-1D run, one cell thick across the axis)::

    profile_plot.py FRAME.h5 --case sod --axis x --out sod.png
        [--left RHO,U,P] [--right RHO,U,P] [--gamma-left G] [--gamma-right G]
        [--x0 X0]

  Four panels: density, velocity, pressure and specific internal energy
  against position along the axis.  Markers are the code (cell values at cell
  centres; the velocity is the nodal velocity along the axis at the nodes),
  the line is the exact Riemann solution (tools/exact/riemann.py) at the
  frame's time.  Defaults are Sod's problem: (1, 0, 1) | (0.125, 0, 0.1),
  gamma 1.4 on both sides, diaphragm at x0 = 0.5.  The title gives the L1
  density error sum_i |rho_i - <rho>_i| dx_i against the cell-averaged exact
  density.

Sedov blast (a 3D octant with the origin at a grid corner)::

    profile_plot.py FRAME.h5 --case sedov --energy E --gamma 1.4 --rho0 1 --out sedov.png

  Three panels: density, pressure and radial velocity of every cell against
  the radius of its centroid (scatter), and the exact spherical Sedov-Taylor
  profile (tools/exact/sedov.py).  E is the energy of the FULL sphere: the
  frame holds one octant, so E = 8 x the deck's &source energy (0.851072 for
  input/sedov3d.nml).

The module also provides the frame readers used by tools/speed_error.py.
Run with /usr/bin/python3 (Debian numpy, h5py, matplotlib); no display needed.
"""

import debian_python  # tools/debian_python.py: Debian's python3 if this one lacks the packages
debian_python.require("h5py", "matplotlib", "numpy")

import argparse
import os
import sys

import numpy as np

sys.dont_write_bytecode = True  # leave no __pycache__ in the source tree
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

AXES = {"x": 0, "y": 1, "z": 2}
SOD_LEFT = (1.0, 0.0, 1.0)
SOD_RIGHT = (0.125, 0.0, 0.1)


# --------------------------------------------------------------------- reading
def read_frame(path):
    """Return a dict with the arrays of one HDF5 frame (h5py index order:
    nodes (nk+1, nj+1, ni+1, 3), cells (nk, nj, ni))."""
    import h5py
    out = {}
    with h5py.File(path, "r") as f:
        for name in ("x", "velocity", "density", "pressure", "energy",
                     "sound_speed", "volume"):
            if name in f:
                out[name] = f[name][()]
        out["time"] = float(f["time"][()])
        out["step"] = int(f["step"][()])
    return out


def frame_materials(path):
    """Number of materials of a frame (its `material_names` attribute,
    "1: air, 2: tnt"; 1 for frames written before the attribute existed)."""
    import h5py
    with h5py.File(path, "r") as f:
        legend = f.attrs.get("material_names", b"")
    if isinstance(legend, bytes):
        legend = legend.decode()
    return max(1, len([s for s in str(legend).split(",") if s.strip()]))


def line_profile(fr, axis="x"):
    """Quasi-1D profile along `axis` of a run one cell thick across it.

    Returns a dict: edges (node coordinate along the axis, averaged over the
    cross-section), centres, density, pressure, energy (cell values), and
    node_u (nodal velocity component along the axis, cross-section average).
    """
    a = AXES[axis]
    x, v = fr["x"], fr["velocity"]
    nk, nj, ni = fr["density"].shape
    n_along = (ni, nj, nk)[a]
    n_other = [n for i, n in enumerate((ni, nj, nk)) if i != a]
    if any(n != 1 for n in n_other):
        raise SystemExit(f"not a quasi-1D run along {axis}: cells (ni, nj, nk) = {(ni, nj, nk)}")
    # h5py order is (k, j, i): axis x -> array axis 2, y -> 1, z -> 0
    arr_axis = 2 - a
    other = tuple(i for i in range(3) if i != arr_axis)
    edges = np.moveaxis(x[..., a], arr_axis, -1).reshape(-1, n_along + 1).mean(axis=0)
    node_u = np.moveaxis(v[..., a], arr_axis, -1).reshape(-1, n_along + 1).mean(axis=0)
    cell = {}
    for name in ("density", "pressure", "energy"):
        cell[name] = fr[name].mean(axis=other) if fr[name].ndim == 3 else fr[name]
    return dict(edges=edges, centres=0.5 * (edges[:-1] + edges[1:]), node_u=node_u, **cell)


def cell_centroids(fr):
    """Cell centroids approximated by the mean of the eight corner nodes,
    shape (nk, nj, ni, 3)."""
    x = fr["x"]
    return 0.125 * (x[:-1, :-1, :-1] + x[:-1, :-1, 1:] + x[:-1, 1:, :-1] + x[:-1, 1:, 1:]
                    + x[1:, :-1, :-1] + x[1:, :-1, 1:] + x[1:, 1:, :-1] + x[1:, 1:, 1:])


def radial_cells(fr):
    """Flattened per-cell radius (of the centroid), density, pressure, radial
    velocity (mean of the 8 corner-node velocities projected on the centroid
    direction) and volume, for a blast centred at the origin."""
    c = cell_centroids(fr)
    v = fr["velocity"]
    vc = 0.125 * (v[:-1, :-1, :-1] + v[:-1, :-1, 1:] + v[:-1, 1:, :-1] + v[:-1, 1:, 1:]
                  + v[1:, :-1, :-1] + v[1:, :-1, 1:] + v[1:, 1:, :-1] + v[1:, 1:, 1:])
    r = np.sqrt((c ** 2).sum(axis=-1))
    ur = (vc * c).sum(axis=-1) / np.where(r > 0.0, r, 1.0)
    return dict(r=r.ravel(), density=fr["density"].ravel(), pressure=fr["pressure"].ravel(),
                ur=ur.ravel(), volume=fr["volume"].ravel())


# --------------------------------------------------------------------- errors
def riemann_l1(prof, rs, t, x0, nsub=200):
    """sum_i |rho_i - <rho>_i| dx_i with the cell-averaged exact density."""
    edges = prof["edges"]
    rho_ex = rs.cell_average(edges, t, x0, nsub=nsub)[0]
    return float(np.sum(np.abs(prof["density"] - rho_ex) * np.diff(edges)))


def make_sedov(gamma, energy, rho0):
    """The exact spherical Sedov solution of tools/exact/sedov.py."""
    from exact.sedov import SedovSolution
    return SedovSolution(gamma, 3, energy, rho0=rho0)


def sedov_l1(cells, sol, t, radius_factor=1.2):
    """Volume-weighted mean |rho - rho_exact(r_c)| over the cells whose
    centroid radius r_c < radius_factor * R_shock(t):
    sum_i V_i |rho_i - rho_exact(r_c,i)| / sum_i V_i.  Returns (L1, R_shock)."""
    rs = float(sol.shock_radius(t))
    m = cells["r"] < radius_factor * rs
    rho_ex = np.asarray(sol.state(cells["r"][m], t)[0], dtype=float)
    vol = cells["volume"][m]
    return float(np.sum(vol * np.abs(cells["density"][m] - rho_ex)) / np.sum(vol)), rs


# --------------------------------------------------------------------- plots
def _triple(text, name):
    try:
        vals = tuple(float(s) for s in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) != 3:
        raise argparse.ArgumentTypeError(f"{name} needs three numbers RHO,U,P, got {text!r}")
    return vals


def plot_riemann(frame, out, axis, left, right, gl, gr, x0):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from exact.riemann import RiemannSolution

    fr = read_frame(frame)
    prof = line_profile(fr, axis)
    t = fr["time"]
    rs = RiemannSolution(*left, gl, *right, gr)
    edges = prof["edges"]
    xf = np.linspace(edges[0], edges[-1], 4001)
    ex = rs.sample(xf, t, x0)
    l1 = riemann_l1(prof, rs, t, x0)
    n = len(prof["density"])

    fig, axs = plt.subplots(2, 2, figsize=(11, 8), sharex=True)
    panels = [("density", prof["centres"], prof["density"], ex[0]),
              ("velocity", edges, prof["node_u"], ex[1]),
              ("pressure", prof["centres"], prof["pressure"], ex[2]),
              ("specific internal energy", prof["centres"], prof["energy"], ex[3])]
    for ax, (label, xc, yc, ye) in zip(axs.flat, panels):
        ax.plot(xf, ye, "-", color="k", lw=1.2, label="exact")
        ax.plot(xc, yc, "o", ms=3 if n <= 200 else 1.5, mfc="none", color="C3", label="lsalepm")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    for ax in axs[1]:
        ax.set_xlabel(axis)
    axs[0, 0].legend(loc="best")
    fig.suptitle(f"{os.path.basename(frame)}: N = {n}, t = {t:.4g}, step {fr['step']}; "
                 f"L1(rho) = {l1:.4e}\n"
                 f"left ({left[0]:g}, {left[1]:g}, {left[2]:g}) gamma {gl:g} | "
                 f"right ({right[0]:g}, {right[1]:g}, {right[2]:g}) gamma {gr:g}, x0 = {x0:g}; "
                 f"p* = {rs.p_star:.5g}, u* = {rs.u_star:.5g}")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(f"{out}: N = {n}, t = {t:.6g}, L1 density error {l1:.6e}")


def plot_sedov(frame, out, energy, gamma, rho0):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fr = read_frame(frame)
    t = fr["time"]
    if t <= 0.0:
        raise SystemExit(f"{frame}: t = 0, nothing to compare")
    cells = radial_cells(fr)
    sol = make_sedov(gamma, energy, rho0)
    l1, rshock = sedov_l1(cells, sol, t)
    # the octant's far corner is at sqrt(3) x the box; ambient cells beyond
    # 1.5 R_shock carry no information
    rmax = min(float(cells["r"].max()), 1.5 * rshock)
    rf = np.linspace(0.0, rmax, 3001)[1:]
    rho_e, u_e, p_e = (np.asarray(a, dtype=float) for a in sol.state(rf, t))
    ncell = cells["r"].size

    fig, axs = plt.subplots(1, 3, figsize=(15, 4.8))
    panels = [("density", cells["density"], rho_e),
              ("pressure", cells["pressure"], p_e),
              ("radial velocity", cells["ur"], u_e)]
    ms = 4 if ncell <= 20000 else 1
    for ax, (label, yc, ye) in zip(axs, panels):
        ax.scatter(cells["r"], yc, s=ms, alpha=0.4, color="C0", lw=0, label="lsalepm cells")
        ax.plot(rf, ye, "-", color="k", lw=1.2, label="exact (spherical)")
        ax.axvline(rshock, color="C3", lw=0.8, ls="--", label=f"R_shock = {rshock:.4g}")
        ax.set_xlabel("radius of the cell centroid")
        ax.set_ylabel(label)
        ax.set_xlim(0.0, rmax)
        ax.grid(alpha=0.3)
    axs[0].legend(loc="upper left", fontsize=8)
    nk, nj, ni = fr["density"].shape
    fig.suptitle(f"{os.path.basename(frame)}: {ni} x {nj} x {nk} cells, t = {t:.4g}, "
                 f"E = {energy:g} (full sphere), gamma {gamma:g}, rho0 {rho0:g}; "
                 f"L1(rho, r < 1.2 R) = {l1:.4e}")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    print(f"{out}: t = {t:.6g}, R_shock = {rshock:.6g}, volume-weighted L1 density error {l1:.6e}")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("frame", help="an HDF5 frame <dir>/<name>_NNNNN.h5")
    p.add_argument("--case", choices=("sod", "sedov"), required=True,
                   help="the exact solution to overlay: sod (a Riemann problem, --left/--right) or "
                        "sedov (--energy); required: the frame does not say which problem it is")
    p.add_argument("--out", help="PNG file (default: the frame name with .png, in the current directory)")
    g = p.add_argument_group("sod / Riemann")
    g.add_argument("--axis", choices=tuple(AXES), default="x")
    g.add_argument("--left", type=lambda s: _triple(s, "--left"), default=SOD_LEFT, metavar="RHO,U,P")
    g.add_argument("--right", type=lambda s: _triple(s, "--right"), default=SOD_RIGHT, metavar="RHO,U,P")
    g.add_argument("--gamma-left", type=float, default=None, help="default: --gamma (1.4)")
    g.add_argument("--gamma-right", type=float, default=None, help="default: --gamma (1.4)")
    g.add_argument("--x0", type=float, default=0.5, help="initial discontinuity (default 0.5)")
    s = p.add_argument_group("sedov")
    s.add_argument("--energy", type=float, help="blast energy of the full sphere (8 x the octant deck's)")
    s.add_argument("--gamma", type=float, default=1.4)
    s.add_argument("--rho0", type=float, default=1.0)
    a = p.parse_args(argv)
    out = a.out or os.path.splitext(os.path.basename(a.frame))[0] + ".png"
    if a.case == "sod":
        gl = a.gamma_left if a.gamma_left is not None else a.gamma
        gr = a.gamma_right if a.gamma_right is not None else a.gamma
        nmat = frame_materials(a.frame)
        if nmat > 1 and a.gamma_left is None and a.gamma_right is None:
            print(f"profile_plot: warning: {a.frame} holds {nmat} materials; the exact solution uses "
                  f"gamma {gl:g} on both sides (give --gamma-left, --gamma-right, --left, --right)",
                  file=sys.stderr)
        plot_riemann(a.frame, out, a.axis, a.left, a.right, gl, gr, a.x0)
    else:
        if a.energy is None:
            p.error("--case sedov needs --energy (full-sphere energy, 8 x the octant deck's source)")
        plot_sedov(a.frame, out, a.energy, a.gamma, a.rho0)


if __name__ == "__main__":
    main()
