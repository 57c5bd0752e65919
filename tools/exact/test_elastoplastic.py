#!/usr/bin/python3
"""Checks of tools/exact/elastoplastic.py (plain script, no pytest).

* both jumps satisfy mass, momentum and energy and the end states lie on
  the yield surface with the Mie-Gruneisen pressure (relative residuals
  below 1e-12);
* the elastic limit's strain is Y/(2G) (ln rho1/rho0);
* as Y -> 0 the precursor vanishes and the plateau is the hydrodynamic
  Hugoniot's, sigma = rho0 (c0 + s1 up) up at up = V/2 (the formula of
  tests/check_particles_impact.py), to 1e-6;
* for a small elastic limit the precursor runs at the longitudinal sound
  speed sqrt((rho0 c0^2 + 4G/3)/rho0), to 1e-4;
* an impact too slow to pass the elastic limit is refused.

Prints "PASS test_elastoplastic" and exits 0, or lists the failures and exits 1.
"""

import os as _os
import sys as _sys
_sys.path.insert(0, _os.path.dirname(_os.path.dirname(_os.path.abspath(__file__))))
import debian_python  # noqa: E402  (tools/debian_python.py)

import math
import os
import sys

sys.dont_write_bytecode = True  # leave no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from elastoplastic import mg_pressure, solve  # noqa: E402

failures = []


def check(name, got, want, tol):
    if not (math.isfinite(got) and abs(got - want) <= tol):
        failures.append(f"{name}: got {got!r}, want {want!r} (tol {tol:.3g})")


# aluminium in cm, g, us (pressures in Mbar), 500 m/s
AL = dict(rho0=2.7, c0=0.533, s1=1.34, gamma0=2.0, g=0.271, y=0.0029)
V = 0.05
s = solve(v=V, **AL)
rho0 = AL["rho0"]
eos = (rho0, AL["c0"], AL["s1"], AL["gamma0"])
# the precursor from rest
check("precursor mass", rho0 * s["U1"], s["rho1"] * (s["U1"] - s["u1"]), 1e-12 * rho0 * s["U1"])
check("precursor momentum", s["sigma1"], rho0 * s["U1"] * s["u1"], 1e-12 * s["sigma1"])
check("precursor energy", s["e1"], 0.5 * s["sigma1"] * (1 / rho0 - 1 / s["rho1"]), 1e-12 * s["e1"])
check("precursor on the yield surface", s["sigma1"], mg_pressure(s["rho1"], s["e1"], *eos) + 2 * AL["y"] / 3,
      1e-12 * s["sigma1"])
check("elastic limit strain ln(rho1/rho0) - Y/2G", math.log(s["rho1"] / rho0), AL["y"] / (2 * AL["g"]), 1e-15)
# the plastic shock
m = s["rho1"] * (s["Up"] - s["u1"])
check("shock mass", m, s["rhof"] * (s["Up"] - s["uf"]), 1e-12 * m)
check("shock momentum", s["sigmaf"] - s["sigma1"], m * (s["uf"] - s["u1"]), 1e-12 * s["sigmaf"])
check("shock energy", s["ef"] - s["e1"], 0.5 * (s["sigmaf"] + s["sigma1"]) * (1 / s["rho1"] - 1 / s["rhof"]),
      1e-12 * s["ef"])
check("plateau on the yield surface", s["sigmaf"], mg_pressure(s["rhof"], s["ef"], *eos) + 2 * AL["y"] / 3,
      1e-12 * s["sigmaf"])
check("plateau velocity V/2", s["uf"], 0.5 * V, 0.0)
if not s["Up"] < s["U1"]:
    failures.append(f"plastic shock {s['Up']} not slower than the precursor {s['U1']}")
# no strength: the hydrodynamic Hugoniot
weak = solve(v=V, **dict(AL, y=1e-12))
up = 0.5 * V
hug = rho0 * (AL["c0"] + AL["s1"] * up) * up
check("Y -> 0: plateau / rho0 Us up", weak["sigmaf"] / hug, 1.0, 1e-6)
check("Y -> 0: precursor stress", weak["sigma1"], 0.0, 1e-9)
# a small elastic limit: the longitudinal sound speed
small = solve(v=V, **dict(AL, y=1e-7))
cl = math.sqrt((rho0 * AL["c0"] ** 2 + 4 * AL["g"] / 3) / rho0)
check("small Y: precursor speed / c_L", small["U1"] / cl, 1.0, 1e-4)
# too slow to yield
try:
    solve(v=0.1 * s["u1"], **AL)
    failures.append("an impact below the elastic limit was not refused")
except ValueError:
    pass

if failures:
    print("FAIL test_elastoplastic")
    for f in failures:
        print("  " + f)
    sys.exit(1)
print("PASS test_elastoplastic")
