"""Exact solution of the 1D Riemann problem of an ideal gas against a
linear-elastic solid (uniaxial strain), PARTICLES.md section 4, rung 4.

The gas (rho, u, p, gamma) lies on one side of the interface x0, the solid
(density rho_s, velocity u_s, normal stress sigma_xx, tension positive, and
longitudinal modulus M = K + 4G/3) on the other.  Out of the interface run

* in the gas, a shock or a rarefaction (Toro, "Riemann Solvers and Numerical
  Methods for Fluid Dynamics", 3rd ed., ch. 4: the pressure function f_K of
  tools/exact/riemann.py);
* in the solid, one longitudinal wave at c_L = sqrt(M / rho_s) relative to
  the undisturbed solid (linear elasticity: the jump relation across it is
  the acoustic one, d(sigma_xx) = -/+ Z du, Z = rho_s c_L, for a wave moving
  into a solid on the right / left).

The star state: the normal traction of the solid equals the gas pressure,
-sigma_xx* = p*, and the normal velocities match.  With the solid's pressure
p_s = -sigma_xx and du = u_right - u_left, p* is the root of

    F(p) = f_gas(p) + (p - p_s) / Z + du = 0,

which is monotone increasing in p (f_gas is), solved by Newton's method with
a bisection safeguard.  Then u* = u_s + (p* - p_s)/Z for a solid on the right
and u* = u_s - (p* - p_s)/Z for a solid on the left.  If F(0) >= 0 the gas
would have to pull on the solid (cavitation at the interface): ValueError.

The solid's wave front is at x0 + (u_s +/- c_L) t (the linear theory's
wave speed relative to the material ahead), its star density
rho_s c_L / (c_L -/+ (u* - u_s)) (mass across the front).

Usage::

    gs = GasSolidSolution(gas=(1.0, 1.0, 1.0, 1.4), solid=(1.0, 0.0, -1.0, 100.0), gas_side="left")
    gs.p_star, gs.u_star
    p, u, rho = gs.sample(x, t, x0)     # p: gas pressure, or -sigma_xx in the solid
    p, u, rho = gs.cell_average(edges, t, x0)
"""

import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from riemann import _Side, star_pressure  # noqa: E402  (the gas's pressure function, star density, root)

__all__ = ["GasSolidSolution"]


class GasSolidSolution:
    """Exact gas / linear-elastic solid Riemann problem (module notes).

    gas = (rho, u, p, gamma); solid = (rho_s, u_s, sigma_xx, M);
    gas_side = "left" or "right" (the solid is on the other side).

    Attributes: p_star (= -sigma_xx* in the solid), u_star, rho_gas_star,
    rho_solid_star, c_solid (c_L), impedance (Z = rho_s c_L), gas_shock, and
    the wave positions per unit time (solid_front, gas_head, gas_tail) in
    the frame where the gas lies on the left (see `sample`).
    """

    def __init__(self, gas, solid, gas_side="left", tol=1.0e-14, max_iter=200):
        if gas_side not in ("left", "right"):
            raise ValueError(f"gas_side must be 'left' or 'right', got {gas_side!r}")
        rho, u, p, g = (float(v) for v in gas)
        rho_s, u_s, sxx, modulus = (float(v) for v in solid)
        for name, v in (("solid density", rho_s), ("longitudinal modulus M", modulus)):
            if not (v > 0.0 and math.isfinite(v)):
                raise ValueError(f"{name} must be positive and finite, got {v}")
        if not (math.isfinite(u_s) and math.isfinite(sxx)):
            raise ValueError("solid velocity and stress must be finite")
        self.gas_side = gas_side
        # Work with the gas on the left: a solid-left problem is its mirror
        # image (x -> -x, velocities change sign, pressures and stresses not).
        sgn = 1.0 if gas_side == "left" else -1.0
        self._sgn = sgn
        self.gas = _Side(rho, sgn * u, p, g, "gas")
        self.rho_s, self.u_s, self.p_s, self.modulus = rho_s, sgn * u_s, -sxx, modulus
        self.c_solid = math.sqrt(modulus / rho_s)
        self.impedance = rho_s * self.c_solid
        self.p_star = self._solve_pressure(tol, max_iter)
        us = self.u_s + (self.p_star - self.p_s) / self.impedance
        self._u = us
        self.u_star = sgn * us
        self.rho_gas_star = self.gas.rho_star(self.p_star)
        self.rho_solid_star = rho_s * self.c_solid / (self.c_solid - (us - self.u_s))
        self.gas_shock = self.p_star > self.gas.p
        G = self.gas
        if self.gas_shock:   # Toro 4.52
            s = G.u - G.a * math.sqrt((G.g + 1.0) / (2.0 * G.g) * self.p_star / G.p + (G.g - 1.0) / (2.0 * G.g))
            self.gas_head = self.gas_tail = s
        else:                # Toro 4.55
            self.gas_head = G.u - G.a
            self.gas_tail = us - G.a * (self.p_star / G.p) ** G.z
        self.solid_front = self.u_s + self.c_solid

    def _func(self, p):
        f, d = self.gas.f(p)
        return f + (p - self.p_s) / self.impedance + (self.u_s - self.gas.u), d + 1.0 / self.impedance

    def _solve_pressure(self, tol, max_iter):
        G = self.gas
        f0 = -2.0 * G.a / (G.g - 1.0) - self.p_s / self.impedance + (self.u_s - G.u)
        if f0 >= 0.0:
            raise ValueError("the gas cannot hold the solid: the interface cavitates "
                             f"(F(0) = {f0} >= 0); the exact solver does not handle it")
        hi = max(G.p, abs(self.p_s), 1.0e-300)
        return star_pressure(self._func, hi, 0.5 * hi, tol, max_iter)

    def sample_speed(self, s):
        """(p, u, rho) on the rays s = (x - x0)/t (array-valued); p is the gas
        pressure on the gas side and -sigma_xx on the solid side."""
        s = self._sgn * np.asarray(s, dtype=float)
        G, ps, us = self.gas, self.p_star, self._u
        p = np.empty_like(s)
        u = np.empty_like(s)
        rho = np.empty_like(s)
        gas = s <= us
        m = gas & (s <= self.gas_head)
        p[m], u[m], rho[m] = G.p, G.u, G.rho
        m = gas & (s > self.gas_tail)
        p[m], u[m], rho[m] = ps, us, self.rho_gas_star
        if not self.gas_shock:  # inside the fan (Toro 4.56)
            m = gas & (s > self.gas_head) & (s <= self.gas_tail)
            c = 2.0 / (G.g + 1.0) + (G.g - 1.0) / ((G.g + 1.0) * G.a) * (G.u - s[m])
            rho[m] = G.rho * c ** (2.0 / (G.g - 1.0))
            u[m] = 2.0 / (G.g + 1.0) * (G.a + 0.5 * (G.g - 1.0) * G.u + s[m])
            p[m] = G.p * c ** (2.0 * G.g / (G.g - 1.0))
        solid = ~gas
        m = solid & (s < self.solid_front)
        p[m], u[m], rho[m] = ps, us, self.rho_solid_star
        m = solid & (s >= self.solid_front)
        p[m], u[m], rho[m] = self.p_s, self.u_s, self.rho_s
        return p, self._sgn * u, rho

    def sample(self, x, t, x0=0.0):
        """Exact (p, u, rho) at positions x and time t > 0, interface at x0 at
        t = 0 (p: gas pressure, or -sigma_xx in the solid)."""
        if t <= 0.0:
            raise ValueError("sample needs t > 0")
        return self.sample_speed((np.asarray(x, dtype=float) - x0) / t)

    def interface(self, t, x0=0.0):
        """Position of the gas-solid interface at time t."""
        return x0 + self.u_star * t

    def cell_average(self, edges, t, x0=0.0, nsub=200):
        """Length averages of (p, u, rho) over the cells [edges[i], edges[i+1]]
        (composite midpoint rule, nsub points per cell)."""
        edges = np.asarray(edges, dtype=float)
        frac = (np.arange(max(int(nsub), 1)) + 0.5) / max(int(nsub), 1)
        xs = edges[:-1, None] + np.diff(edges)[:, None] * frac[None, :]
        p, u, rho = self.sample(xs.ravel(), t, x0)
        return tuple(a.reshape(xs.shape).mean(axis=1) for a in (p, u, rho))
