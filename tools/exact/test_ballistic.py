#!/usr/bin/python3
"""Checks of tools/exact/ballistic.py (plain script, no pytest).

* the closed-form u(t) against a numerical integration (classical RK4,
  4000 steps) of m du/dt = p0 (1 - a u)^k from rest, and the closed-form
  travel against the trapezoid integral of u;
* by hand: u ~ p0 t / m for small t (first step of the slab at rest), u
  below the escape speed 2 c0 / (gamma - 1), half of it at
  1 + a (k-1) p0 t / m = 2^(k-1), the pressure on
  the slab p0 (1 - a u)^k = m du/dt;
* the validity bound lies between L/c0 + L/(c0 + (3-gamma)/2 u_max) and
  2 L/c0 and satisfies its defining equation.

Prints "PASS test_ballistic" and exits 0, or lists the failures and exits 1.
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
from ballistic import Ballistic  # noqa: E402

failures = []


def check(name, got, want, tol):
    if not (math.isfinite(got) and abs(got - want) <= tol):
        failures.append(f"{name}: got {got!r}, want {want!r} (tol {tol:.3g})")


for p0, rho0, g, m, L in ((1.0, 1.0, 1.4, 1.0, 1.0), (3.0, 0.5, 5.0 / 3.0, 0.2, 2.0), (1.0e5, 1.2, 1.3, 50.0, 0.5)):
    b = Ballistic(p0, rho0, g, m, L)
    name = f"p0 {p0} rho0 {rho0} gamma {g} m {m}"
    t_end = 3.0 * L / b.c0
    n = 4000
    h = t_end / n
    u = 0.0
    us = [0.0]
    for _ in range(n):   # RK4: error ~ h^4, far below the tolerance 1e-9 of u_escape
        k1 = b.rhs(u)
        k2 = b.rhs(u + 0.5 * h * k1)
        k3 = b.rhs(u + 0.5 * h * k2)
        k4 = b.rhs(u + h * k3)
        u += h * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
        us.append(u)
    us = np.array(us)
    ts = np.linspace(0.0, t_end, n + 1)
    escape = 2.0 * b.c0 / (g - 1.0)
    check(name + " u(t) vs RK4 (max over t)", float(np.max(np.abs(b.velocity(ts) - us))), 0.0, 1e-9 * escape)
    # travel: trapezoid of the RK4 velocities, error ~ h^2 u''
    trap = float(np.sum(0.5 * (us[1:] + us[:-1])) * h)
    check(name + " travel vs trapezoid", float(b.travel(t_end)), trap, 1e-6 * trap)
    # small t: u = p0 t/m (1 - O(t))
    t1 = 1e-6 * m / p0 * b.c0
    check(name + " small-t slope", float(b.velocity(t1)) / t1, p0 / m, 1e-5 * p0 / m)
    check(name + " below escape speed", float(np.max(b.velocity(ts)) < escape), 1.0, 0.0)
    # half the escape speed where 1 + a (k-1) p0 t/m = 2^(k-1), by hand
    th = (2.0 ** (b.k - 1.0) - 1.0) * m / (b.a * (b.k - 1.0) * p0)
    check(name + " half the escape speed", float(b.velocity(th)) / escape, 0.5, 1e-12)
    # m du/dt (central difference) = pressure on the slab
    t2, dt = 0.7 * t_end, 1e-5 * t_end
    dudt = float(b.velocity(t2 + dt) - b.velocity(t2 - dt)) / (2.0 * dt)
    check(name + " m du/dt = p(slab)", m * dudt, float(b.pressure(t2)), 1e-6 * p0)
    tv = b.valid_until()
    lo = L / b.c0 + L / (b.c0 + 0.5 * (3.0 - g) * escape)
    check(name + " validity bound in range", float(lo <= tv <= 2.0 * L / b.c0), 1.0, 0.0)
    check(name + " validity bound equation", tv, L / b.c0 + L / (b.c0 + 0.5 * (3.0 - g) * float(b.velocity(tv))),
          1e-12 * tv)

try:
    Ballistic(1.0, 1.0, 1.0, 1.0, 1.0)
    failures.append("gamma = 1: no ValueError")
except ValueError:
    pass

if failures:
    print("\n".join(failures))
    print(f"FAIL test_ballistic ({len(failures)} failures)")
    sys.exit(1)
print("PASS test_ballistic")
