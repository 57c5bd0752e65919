#!/usr/bin/python3
"""Checks of tools/exact/gas_solid.py (plain script, no pytest).

Limits checkable by hand or against tools/exact/riemann.py:
* a rigid solid (M -> infinity) is a wall: the gas reflects off it as off
  its mirror image (the symmetric gas Riemann problem of riemann.py), also
  for a moving wall (the same problem in the wall's frame);
* equal pressures (-sigma_xx = p) and velocities: no waves, the initial
  states everywhere;
* a weak jump: the acoustic answer p* - p = Z_g Z_s / (Z_g + Z_s) (u_L - u_R);
* the jump conditions of the solution itself: Rankine-Hugoniot mass and
  momentum across the gas shock, the Riemann invariant across the gas fan,
  mass and momentum across the solid's front;
* the gas on the right is the mirror image of the gas on the left;
* a gas that cannot hold the solid (cavitation) raises ValueError.

Prints "PASS test_gas_solid" and exits 0, or lists the failures and exits 1.
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
from gas_solid import GasSolidSolution  # noqa: E402
from riemann import RiemannSolution  # noqa: E402

failures = []


def check(name, got, want, tol):
    if not (math.isfinite(got) and abs(got - want) <= tol):
        failures.append(f"{name}: got {got!r}, want {want!r} (tol {tol:.3g})")


# ---- rigid solid = wall: the gas against its mirror image --------------------
# Z = 1e7: the wall moves by (p* - p_s)/Z ~ 1e-7, which shifts p* by about
# Z_gas 1e-7 ~ 1e-6; tolerance 1e-5 relative.
for u_gas, u_wall in ((1.0, 0.0), (-0.8, 0.0), (1.0, 0.3), (2.0, -0.5)):
    rho, p, g = 1.0, 1.0, 1.4
    for side in ("left", "right"):
        ug = u_gas if side == "left" else -u_gas
        uw = u_wall if side == "left" else -u_wall
        gs = GasSolidSolution((rho, ug, p, g), (1.0, uw, -3.0, 1.0e14), gas_side=side)
        # in the wall's frame the gas moves at u_gas - u_wall towards it
        rs = RiemannSolution(rho, u_gas - u_wall, p, g, rho, -(u_gas - u_wall), p, g)
        name = f"rigid wall ({side}, u_gas {ug}, u_wall {uw})"
        check(name + " p*", gs.p_star, rs.p_star, 1e-5 * rs.p_star)
        check(name + " u*", gs.u_star, uw, 1e-6)
        rg = gs.rho_gas_star
        check(name + " rho_gas*", rg, rs.rho_star_l, 1e-5 * rs.rho_star_l)
        check(name + " shock", float(gs.gas_shock), float(u_gas - u_wall > 0.0), 0.0)

# ---- no waves ------------------------------------------------------------------
gs = GasSolidSolution((2.0, 0.5, 3.0, 1.4), (7.0, 0.5, -3.0, 50.0))
check("equal states p*", gs.p_star, 3.0, 1e-12)
check("equal states u*", gs.u_star, 0.5, 1e-12)
x = np.linspace(-1.0, 1.0, 41)
p, u, rho = gs.sample(x, 0.1, 0.0)
gas = x < gs.interface(0.1)
check("equal states sampled p", float(np.max(np.abs(p - 3.0))), 0.0, 1e-12)
check("equal states sampled u", float(np.max(np.abs(u - 0.5))), 0.0, 1e-12)
check("equal states sampled rho", float(np.max(np.abs(rho - np.where(gas, 2.0, 7.0)))), 0.0, 1e-12)

# ---- acoustic limit --------------------------------------------------------------
# du = 1e-4: the nonlinear terms are O(du^2): relative 1e-3 of the jump.
rho, p, g, rho_s, modulus, du = 1.0, 1.0, 1.4, 3.0, 12.0, 1.0e-4
zg, zs = rho * math.sqrt(g * p / rho), math.sqrt(rho_s * modulus)
for side, u_g in (("left", du), ("right", -du), ("left", -du)):
    gs = GasSolidSolution((rho, u_g, p, g), (rho_s, 0.0, -p, modulus), gas_side=side)
    want = zg * zs / (zg + zs) * abs(du) * (1.0 if (side == "left") == (u_g > 0) else -1.0)
    check(f"acoustic ({side}, u {u_g}) p* - p", gs.p_star - p, want, 1e-3 * abs(want))
    check(f"acoustic ({side}, u {u_g}) u*", gs.u_star, (want / zs) * (1.0 if side == "left" else -1.0),
          1e-3 * abs(want / zs))

# ---- jump conditions of the solution -------------------------------------------
# shock: gas moving into the solid; fan: a high-pressure gas at rest.
for gas, solid in (((1.0, 1.0, 1.0, 1.4), (1.0, 0.0, -1.0, 100.0)),
                   ((1.0, 0.0, 10.0, 1.4), (4.0, 0.2, -1.0, 200.0)),
                   ((0.5, -0.3, 2.0, 5.0 / 3.0), (2.0, 0.4, 0.5, 30.0))):
    gs = GasSolidSolution(gas, solid)
    r0, u0, p0, g = gas
    rs_, us_, sxx, modulus = solid
    name = f"gas {gas} solid {solid}"
    ps, ust = gs.p_star, gs.u_star
    if gs.gas_shock:
        s = gs.gas_head
        check(name + " shock mass", r0 * (u0 - s), gs.rho_gas_star * (ust - s), 1e-12 * abs(r0 * s) + 1e-13)
        check(name + " shock momentum", p0 + r0 * (u0 - s) ** 2, ps + gs.rho_gas_star * (ust - s) ** 2, 1e-11 * ps)
    else:
        a0, a1 = math.sqrt(g * p0 / r0), math.sqrt(g * ps / gs.rho_gas_star)
        check(name + " fan invariant", ust + 2.0 * a1 / (g - 1.0), u0 + 2.0 * a0 / (g - 1.0), 1e-12)
        check(name + " fan isentrope", ps / gs.rho_gas_star ** g, p0 / r0 ** g, 1e-12 * p0 / r0 ** g)
    c = math.sqrt(modulus / rs_)
    check(name + " solid momentum", ps - (-sxx), rs_ * c * (ust - us_), 1e-12 * max(1.0, ps))
    check(name + " solid mass", rs_ * c, gs.rho_solid_star * (c - (ust - us_)), 1e-12 * rs_ * c)
    # the sampled solution has the star state on both sides of the interface
    t = 0.01
    eps = 1e-9
    pl, ul, _ = gs.sample([gs.interface(t) - eps], t)
    pr, ur, _ = gs.sample([gs.interface(t) + eps], t)
    check(name + " sampled p* (gas)", float(pl[0]), ps, 1e-12 * ps)
    check(name + " sampled p* (solid)", float(pr[0]), ps, 1e-12 * ps)
    check(name + " sampled u* (both)", float(ul[0] - ur[0]), 0.0, 1e-12)
    # mirror image: the gas on the right
    gm = GasSolidSolution((r0, -u0, p0, g), (rs_, -us_, sxx, modulus), gas_side="right")
    check(name + " mirror p*", gm.p_star, ps, 1e-12 * ps)
    check(name + " mirror u*", gm.u_star, -ust, 1e-12)
    xs = np.linspace(-0.5, 0.5, 101)
    pa, ua, ra = gs.sample(xs, 0.02)
    pb, ub, rb = gm.sample(-xs, 0.02)
    check(name + " mirror sampled", float(np.max(np.abs(pa - pb)) + np.max(np.abs(ua + ub))
                                         + np.max(np.abs(ra - rb))), 0.0, 1e-12)

# ---- cavitation -------------------------------------------------------------------
try:
    GasSolidSolution((1.0, -10.0, 1.0, 1.4), (1.0, 0.0, -1.0, 100.0))
    failures.append("cavitation: no ValueError")
except ValueError:
    pass

if failures:
    print("\n".join(failures))
    print(f"FAIL test_gas_solid ({len(failures)} failures)")
    sys.exit(1)
print("PASS test_gas_solid")
