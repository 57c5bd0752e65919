"""Lagrange ballistic problem (gas-driven piston), PARTICLES.md section 4,
rung 5: an ideal gas at rest (p0, rho0, gamma) fills a tube 0 < x < L closed
at x = 0 (the breech); at x = L a free rigid slab of areal mass m (mass per
unit cross-section) starts from rest with vacuum ahead of it.

While the gas behind the slab is the simple (left-facing) rarefaction that
the slab's motion sends back into the gas at rest, the Riemann invariant
u + 2c/(gamma-1) = 2c0/(gamma-1) holds at the slab, so its pressure is
p0 (1 - a u)^k (isentrope) and

    m du/dt = p0 (1 - a u)^k,   a = (gamma - 1)/(2 c0),  k = 2 gamma/(gamma - 1),

whose solution from rest is

    u(t) = (1/a) [1 - (1 + a (k - 1) p0 t / m)^(-1/(k-1))],

tending to the escape speed 1/a = 2 c0/(gamma - 1); the slab's travel is
x(t) = L + int_0^t u. The solution holds until the rarefaction's head,
reflected at the breech at t = L/c0, catches the slab. `valid_until` gives
a lower bound of that time: the reflected head moves at u + c = c0 +
(3 - gamma)/2 u <= c0 + (3 - gamma)/2 u(t) through the simple wave (every
state there left the slab earlier, and u(t) increases), and must cover at
least L, so it arrives no earlier than the root t* of
t = L/c0 + L/(c0 + (3 - gamma)/2 u(t)) (about 2L/c0 for a slow slab).

Usage::

    b = Ballistic(p0=1.0, rho0=1.0, gamma=1.4, m=1.0, length=1.0)
    b.velocity(t), b.travel(t), b.pressure(t), b.valid_until()
"""

import math

import numpy as np

__all__ = ["Ballistic"]


class Ballistic:
    """Exact slab velocity of the Lagrange ballistic problem (module notes)."""

    def __init__(self, p0, rho0, gamma, m, length):
        for name, v in (("p0", p0), ("rho0", rho0), ("m", m), ("length", length)):
            if not (v > 0.0 and math.isfinite(v)):
                raise ValueError(f"{name} must be positive and finite, got {v}")
        if not (gamma > 1.0 and math.isfinite(gamma)):
            raise ValueError(f"gamma must be > 1, got {gamma}")
        self.p0, self.rho0, self.gamma, self.m, self.length = (float(v) for v in (p0, rho0, gamma, m, length))
        self.c0 = math.sqrt(gamma * p0 / rho0)
        self.a = (gamma - 1.0) / (2.0 * self.c0)
        self.k = 2.0 * gamma / (gamma - 1.0)

    def velocity(self, t):
        """Slab velocity u(t) (closed form), t >= 0."""
        t = np.asarray(t, dtype=float)
        km1 = self.k - 1.0
        return (1.0 - (1.0 + self.a * km1 * self.p0 * t / self.m) ** (-1.0 / km1)) / self.a

    def travel(self, t):
        """Slab displacement int_0^t u (closed form)."""
        t = np.asarray(t, dtype=float)
        km1, a = self.k - 1.0, self.a
        b = a * km1 * self.p0 / self.m
        # int (1 + b s)^(-1/km1) ds = [(1 + b s)^(1 - 1/km1) - 1] / (b (1 - 1/km1)), k - 1 > 1 always
        e = 1.0 - 1.0 / km1
        return (t - ((1.0 + b * t) ** e - 1.0) / (b * e)) / a

    def pressure(self, t):
        """Gas pressure on the slab, p0 (1 - a u)^k."""
        return self.p0 * (1.0 - self.a * self.velocity(t)) ** self.k

    def rhs(self, u):
        """du/dt of the ODE, p0 (1 - a u)^k / m."""
        return self.p0 * (1.0 - self.a * u) ** self.k / self.m

    def valid_until(self):
        """Lower bound of the time the reflected rarefaction reaches the slab
        (module notes), by bisection of t - L/c0 - L/(c0 + (3-gamma)/2 u(t))."""
        c0, L, g = self.c0, self.length, self.gamma

        def h(t):
            return t - L / c0 - L / (c0 + 0.5 * (3.0 - g) * float(self.velocity(t)))

        lo, hi = L / c0, 2.0 * L / c0   # h(lo) < 0 <= h(hi)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if h(mid) < 0.0:
                lo = mid
            else:
                hi = mid
        return lo
