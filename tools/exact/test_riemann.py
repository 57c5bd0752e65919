#!/usr/bin/python3
"""Checks of tools/exact/riemann.py (plain script, no pytest).

Star states against Toro, "Riemann Solvers and Numerical Methods for Fluid
Dynamics", 3rd ed., table 4.3 (tests 1, 2, 3, 5; gamma = 1.4), to the digits
published, and the two-gamma Sod problem (gamma 2 | 1.4) against the project's
Fortran solver (tests/exact_riemann.f90) to 1e-9.  Also checks consistency:
the sampled solution reproduces the star states and the initial states, cell
averages of constant states are exact, and vacuum raises.

Prints "PASS test_riemann" and exits 0, or lists the failures and exits 1.
"""

import os as _os
import sys as _sys
_sys.path.insert(0, _os.path.dirname(_os.path.dirname(_os.path.abspath(__file__))))
import debian_python  # noqa: E402  (tools/debian_python.py)
debian_python.require("numpy")

import math
import os
import sys

import numpy as np

sys.dont_write_bytecode = True  # leave no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from riemann import RiemannSolution  # noqa: E402

failures = []


def check(name, got, want, rel=None, abs_=None):
    """Record a failure unless |got - want| <= max(rel*|want|, abs_)."""
    tol = 0.0
    if rel is not None:
        tol = max(tol, rel * abs(want))
    if abs_ is not None:
        tol = max(tol, abs_)
    ok = math.isfinite(got) and abs(got - want) <= tol
    if not ok:
        failures.append(f"{name}: got {got!r}, want {want!r} (tol {tol:.3g})")
    return ok


def published(value_str):
    """Tolerance for a published figure: half a unit in its last digit,
    but never tighter than relative 1e-5."""
    v = float(value_str)
    if "." in value_str:
        dec = len(value_str.split(".")[1])
    else:
        dec = 0
    return max(0.5 * 10.0 ** (-dec), 1.0e-5 * abs(v))


def star_case(name, states, refs):
    rs = RiemannSolution(*states)
    for attr, ref in refs.items():
        check(f"{name} {attr}", getattr(rs, attr), float(ref), abs_=published(ref))
    return rs


# Toro table 4.3 (gamma 1.4 both sides)
g = 1.4
sod = star_case("Toro 1 (Sod)", (1.0, 0.0, 1.0, g, 0.125, 0.0, 0.1, g),
                {"p_star": "0.30313", "u_star": "0.92745",
                 "rho_star_l": "0.42632", "rho_star_r": "0.26557"})
t2 = star_case("Toro 2 (123)", (1.0, -2.0, 0.4, g, 1.0, 2.0, 0.4, g),
               {"p_star": "0.00189", "u_star": "0.0"})
check("Toro 2 u* symmetric", t2.u_star, 0.0, abs_=1e-12)
check("Toro 2 rho*L = rho*R", t2.rho_star_l, t2.rho_star_r, rel=1e-12)
star_case("Toro 3", (1.0, 0.0, 1000.0, g, 1.0, 0.0, 0.01, g),
          {"p_star": "460.894", "u_star": "19.5975"})
star_case("Toro 5", (5.99924, 19.5975, 460.894, g, 5.99242, -6.19633, 46.0950, g),
          {"p_star": "1691.64", "u_star": "8.68975"})
# Toro test 4 (also in table 4.3)
star_case("Toro 4", (1.0, 0.0, 0.01, g, 1.0, 0.0, 100.0, g),
          {"p_star": "46.0950", "u_star": "-6.19633"})

# two-gamma Sod, values from the project's Fortran solver
tg = RiemannSolution(1.0, 0.0, 2.0, 2.0, 0.125, 0.0, 0.1, 1.4)
check("two-gamma p*", tg.p_star, 0.43033193720, abs_=1e-9)
check("two-gamma u*", tg.u_star, 1.2757096813, abs_=1e-9)

# consistency of sampling: star states, far field, energies per side
for name, rs, gl, gr in (("Sod", sod, 1.4, 1.4), ("two-gamma", tg, 2.0, 1.4)):
    t = 0.2
    eps = 1e-9
    x = np.array([-10.0, rs.u_star * t - eps, rs.u_star * t + eps, 10.0])
    rho, u, p, e = rs.sample(x, t, 0.0)
    L, R = rs.left, rs.right
    check(f"{name} far left rho", rho[0], L.rho, rel=1e-14)
    check(f"{name} far right rho", rho[3], R.rho, rel=1e-14)
    check(f"{name} star-left rho", rho[1], rs.rho_star_l, rel=1e-12)
    check(f"{name} star-right rho", rho[2], rs.rho_star_r, rel=1e-12)
    check(f"{name} star-left p", p[1], rs.p_star, rel=1e-12)
    check(f"{name} star-right u", u[2], rs.u_star, rel=1e-12)
    check(f"{name} left e", e[0], L.p / ((gl - 1.0) * L.rho), rel=1e-14)
    check(f"{name} star-right e", e[2], rs.p_star / ((gr - 1.0) * rs.rho_star_r), rel=1e-12)
    # continuity across the rarefaction tail
    xt = rs.sl_tail * t
    r2 = rs.sample(np.array([xt - 1e-10, xt + 1e-10]), t, 0.0)
    check(f"{name} fan tail continuity", r2[0][0], r2[0][1], rel=1e-8)
    # cell averages: exact on constant states; mass-weighted u in a mixed cell
    edges = np.array([-1.0, -0.9, 0.9, 1.0])
    ra, ua, pa, ea = rs.cell_average(edges, t, 0.0, nsub=400)
    check(f"{name} average left constant", ra[0], L.rho, rel=1e-14)
    check(f"{name} average right constant", pa[2], R.p, rel=1e-14)
    # the middle cell holds all the waves; the end states are at rest, so no
    # mass crosses its edges and it keeps its initial mass (to quadrature error)
    mass0 = L.rho * 0.9 + R.rho * 0.9
    check(f"{name} mass in the wave cell", ra[1] * 1.8, mass0, rel=2e-3)

# initial data for t = 0
r0 = sod.sample(np.array([0.2, 0.7]), 0.0, 0.5)
check("t = 0 left", r0[0][0], 1.0, rel=0.0, abs_=0.0)
check("t = 0 right", r0[0][1], 0.125, rel=0.0, abs_=0.0)

# vacuum must raise
try:
    RiemannSolution(1.0, -20.0, 1.0, 1.4, 1.0, 20.0, 1.0, 1.4)
    failures.append("vacuum: no exception")
except ValueError:
    pass
# bad input must raise
for bad in ((0.0, 0.0, 1.0, 1.4, 1.0, 0.0, 1.0, 1.4), (1.0, 0.0, 1.0, 1.0, 1.0, 0.0, 1.0, 1.4)):
    try:
        RiemannSolution(*bad)
        failures.append(f"bad input {bad}: no exception")
    except ValueError:
        pass

if failures:
    for f in failures:
        print("FAIL", f)
    print(f"FAIL test_riemann ({len(failures)} failures)")
    sys.exit(1)
print("PASS test_riemann")
