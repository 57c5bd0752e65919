"""Exact Riemann solver for the 1D Euler equations with ideal gases.

The left and right states may have different ratios of specific heats
(gamma_L, gamma_R); the contact separates the two gases, so each side keeps
its own gamma.  Method: Toro, "Riemann Solvers and Numerical Methods for
Fluid Dynamics", 3rd ed., chapter 4:

* the star pressure p* is the root of
      f(p) = f_L(p) + f_R(p) + (u_R - u_L) = 0,
  where f_K is the shock (Rankine-Hugoniot, p > p_K) or rarefaction
  (isentropic, p <= p_K) relation of side K with its own gamma (Toro 4.6-4.7);
  f is monotone increasing and concave, so Newton's method with a bisection
  safeguard on a bracket converges from any positive start;
* u* = (u_L + u_R)/2 + (f_R(p*) - f_L(p*))/2  (Toro 4.9);
* the star densities follow from the shock or isentrope relations
  (Toro 4.50, 4.53, 4.57, 4.60) and the solution is sampled on rays
  S = (x - x0)/t as in Toro section 4.5.

Vacuum (the pressure positivity condition, Toro 4.40, fails) raises
ValueError; so do non-positive densities or pressures and gamma <= 1.

Usage::

    rs = RiemannSolution(1.0, 0.0, 1.0, 1.4, 0.125, 0.0, 0.1, 1.4)
    rs.p_star, rs.u_star, rs.rho_star_l, rs.rho_star_r
    rho, u, p, e = rs.sample(x, t, x0)
    rho, u, p, e = rs.cell_average(edges, t, x0, nsub=200)

Here e is the specific internal energy p / ((gamma - 1) rho).
"""

import math

import numpy as np

__all__ = ["RiemannSolution"]


class _Side:
    """Constants of one initial state (Toro 4.8 and the gamma combinations)."""

    def __init__(self, rho, u, p, g, name):
        if not (rho > 0.0 and math.isfinite(rho)):
            raise ValueError(f"{name} density must be positive and finite, got {rho}")
        if not (p > 0.0 and math.isfinite(p)):
            raise ValueError(f"{name} pressure must be positive and finite, got {p}")
        if not (g > 1.0 and math.isfinite(g)):
            raise ValueError(f"{name} gamma must be > 1, got {g}")
        if not math.isfinite(u):
            raise ValueError(f"{name} velocity must be finite, got {u}")
        self.rho, self.u, self.p, self.g = float(rho), float(u), float(p), float(g)
        self.a = math.sqrt(g * p / rho)              # sound speed
        self.A = 2.0 / ((g + 1.0) * rho)             # shock constants (Toro 4.8)
        self.B = (g - 1.0) / (g + 1.0) * p
        self.z = (g - 1.0) / (2.0 * g)               # isentrope exponent

    def f(self, p):
        """Toro's pressure function f_K(p) and its derivative."""
        if p > self.p:  # shock
            q = math.sqrt(self.A / (p + self.B))
            return (p - self.p) * q, q * (1.0 - 0.5 * (p - self.p) / (p + self.B))
        # rarefaction
        r = (p / self.p) ** self.z
        return (2.0 * self.a / (self.g - 1.0)) * (r - 1.0), \
            (p / self.p) ** (-(self.g + 1.0) / (2.0 * self.g)) / (self.rho * self.a)

    def rho_star(self, p):
        """Density behind the wave of this side at star pressure p."""
        g = self.g
        ratio = p / self.p
        if p > self.p:  # shock (Toro 4.50 / 4.57)
            gm = (g - 1.0) / (g + 1.0)
            return self.rho * (ratio + gm) / (gm * ratio + 1.0)
        return self.rho * ratio ** (1.0 / g)  # isentrope (Toro 4.53 / 4.60)


def star_pressure(func, hi, guess, tol, max_iter):
    """The root p > 0 of an increasing func(p) -> (f, df/dp) with f(0+) < 0:
    bracket [lo, hi] with f(lo) < 0 < f(hi) (hi grown by 4 from the given
    one), then Newton from guess (clipped into the bracket), bisecting
    whenever Newton leaves the bracket."""
    lo = 0.0
    while func(hi)[0] < 0.0:
        lo, hi = hi, 4.0 * hi
        if hi > 1.0e300:
            raise RuntimeError("could not bracket the star pressure")
    p = min(guess, hi)
    if p <= lo:
        p = 0.5 * (lo + hi)
    for _ in range(max_iter):
        fv, dv = func(p)
        if fv == 0.0:
            return p
        if fv < 0.0:
            lo = max(lo, p)
        else:
            hi = min(hi, p)
        pn = p - fv / dv if dv > 0.0 else 0.5 * (lo + hi)
        if not (lo < pn < hi):          # Newton left the bracket: bisect
            pn = 0.5 * (lo + hi)
        if abs(pn - p) <= tol * 0.5 * (pn + p) or hi - lo <= tol * hi:
            return pn
        p = pn
    raise RuntimeError("star pressure iteration did not converge")


class RiemannSolution:
    """Exact solution of the ideal-gas Riemann problem (two gammas allowed).

    Attributes: p_star, u_star, rho_star_l, rho_star_r, and the wave speeds
    (shock speed or head/tail of the rarefaction) of each side.
    """

    def __init__(self, rhol, ul, pl, gl, rhor, ur, pr, gr, tol=1.0e-14, max_iter=200):
        self.left = L = _Side(rhol, ul, pl, gl, "left")
        self.right = R = _Side(rhor, ur, pr, gr, "right")
        du = R.u - L.u
        # pressure positivity condition (Toro 4.40, per-side gamma)
        if 2.0 * L.a / (L.g - 1.0) + 2.0 * R.a / (R.g - 1.0) <= du:
            raise ValueError("vacuum is generated: the exact solver does not handle it "
                             f"(2aL/(gL-1) + 2aR/(gR-1) <= uR - uL = {du})")
        self.p_star = self._solve_pressure(tol, max_iter)
        fl, _ = L.f(self.p_star)
        fr, _ = R.f(self.p_star)
        self.u_star = 0.5 * (L.u + R.u) + 0.5 * (fr - fl)
        self.rho_star_l = L.rho_star(self.p_star)
        self.rho_star_r = R.rho_star(self.p_star)
        self._wave_speeds()

    # ---------------------------------------------------------------- p*
    def _func(self, p):
        fl, dl = self.left.f(p)
        fr, dr = self.right.f(p)
        return fl + fr + (self.right.u - self.left.u), dl + dr

    def _solve_pressure(self, tol, max_iter):
        L, R = self.left, self.right
        # bracket [lo, hi] with f(lo) < 0 < f(hi); f(0+) < 0 is the
        # no-vacuum condition checked above, f -> +inf as p -> inf.
        # start: primitive-variable (linearised) guess
        pvrs = 0.5 * (L.p + R.p) - 0.125 * (R.u - L.u) * (L.rho + R.rho) * (L.a + R.a)
        return star_pressure(self._func, max(L.p, R.p), max(pvrs, 1.0e-6 * min(L.p, R.p)), tol, max_iter)

    # ---------------------------------------------------------------- waves
    def _wave_speeds(self):
        L, R, ps, us = self.left, self.right, self.p_star, self.u_star
        if ps > L.p:  # left shock (Toro 4.52)
            self.left_shock = True
            s = L.u - L.a * math.sqrt((L.g + 1.0) / (2.0 * L.g) * ps / L.p + (L.g - 1.0) / (2.0 * L.g))
            self.sl_head = self.sl_tail = s
        else:         # left rarefaction (Toro 4.55)
            self.left_shock = False
            self.sl_head = L.u - L.a
            self.sl_tail = us - L.a * (ps / L.p) ** L.z
        if ps > R.p:  # right shock (Toro 4.59)
            self.right_shock = True
            s = R.u + R.a * math.sqrt((R.g + 1.0) / (2.0 * R.g) * ps / R.p + (R.g - 1.0) / (2.0 * R.g))
            self.sr_head = self.sr_tail = s
        else:         # right rarefaction (Toro 4.62)
            self.right_shock = False
            self.sr_head = R.u + R.a
            self.sr_tail = us + R.a * (ps / R.p) ** R.z

    # ---------------------------------------------------------------- sampling
    def sample_speed(self, s):
        """State (rho, u, p, e) on the rays s = (x - x0)/t (array-valued)."""
        s = np.asarray(s, dtype=float)
        L, R, ps, us = self.left, self.right, self.p_star, self.u_star
        rho = np.empty_like(s)
        u = np.empty_like(s)
        p = np.empty_like(s)
        g = np.where(s <= us, L.g, R.g)

        # left of the contact
        left = s <= us
        # region L (ahead of the left wave)
        m = left & (s <= self.sl_head)
        rho[m], u[m], p[m] = L.rho, L.u, L.p
        # star-left region
        m = left & (s > self.sl_tail)
        rho[m], u[m], p[m] = self.rho_star_l, us, ps
        if not self.left_shock:  # inside the left fan (Toro 4.56)
            m = left & (s > self.sl_head) & (s <= self.sl_tail)
            c = 2.0 / (L.g + 1.0) + (L.g - 1.0) / ((L.g + 1.0) * L.a) * (L.u - s[m])
            rho[m] = L.rho * c ** (2.0 / (L.g - 1.0))
            u[m] = 2.0 / (L.g + 1.0) * (L.a + 0.5 * (L.g - 1.0) * L.u + s[m])
            p[m] = L.p * c ** (2.0 * L.g / (L.g - 1.0))

        # right of the contact
        right = ~left
        m = right & (s >= self.sr_head)
        rho[m], u[m], p[m] = R.rho, R.u, R.p
        m = right & (s < self.sr_tail)
        rho[m], u[m], p[m] = self.rho_star_r, us, ps
        if not self.right_shock:  # inside the right fan (Toro 4.63)
            m = right & (s < self.sr_head) & (s >= self.sr_tail)
            c = 2.0 / (R.g + 1.0) - (R.g - 1.0) / ((R.g + 1.0) * R.a) * (R.u - s[m])
            rho[m] = R.rho * c ** (2.0 / (R.g - 1.0))
            u[m] = 2.0 / (R.g + 1.0) * (-R.a + 0.5 * (R.g - 1.0) * R.u + s[m])
            p[m] = R.p * c ** (2.0 * R.g / (R.g - 1.0))

        e = p / ((g - 1.0) * rho)
        return rho, u, p, e

    def sample(self, x, t, x0=0.0):
        """Exact (rho, u, p, e) at positions x and time t, diaphragm at x0.

        For t <= 0 the initial data are returned (left state for x < x0).
        """
        x = np.asarray(x, dtype=float)
        if t <= 0.0:
            L, R = self.left, self.right
            lm = x < x0
            rho = np.where(lm, L.rho, R.rho)
            u = np.where(lm, L.u, R.u)
            p = np.where(lm, L.p, R.p)
            g = np.where(lm, L.g, R.g)
            return rho, u, p, p / ((g - 1.0) * rho)
        return self.sample_speed((x - x0) / t)

    def cell_average(self, edges, t, x0=0.0, nsub=200):
        """Averages of the exact solution over the cells [edges[i], edges[i+1]].

        rho and p are volume (length) averages; u and e are mass-weighted
        (momentum / mass and internal energy / mass), so they are what a
        conservative scheme carries per cell.  Quadrature: composite midpoint
        rule with nsub equal sub-intervals per cell (exact for the constant
        states; a discontinuity is located to within one sub-interval).
        Returns four arrays of length len(edges) - 1.
        """
        edges = np.asarray(edges, dtype=float)
        if edges.ndim != 1 or edges.size < 2:
            raise ValueError("edges must be a 1D array of at least two points")
        nsub = max(int(nsub), 1)
        xa, xb = edges[:-1], edges[1:]
        frac = (np.arange(nsub) + 0.5) / nsub
        xs = xa[:, None] + (xb - xa)[:, None] * frac[None, :]
        rho, u, p, e = self.sample(xs.ravel(), t, x0)
        shape = xs.shape
        rho, u, p, e = (a.reshape(shape) for a in (rho, u, p, e))
        mass = rho.sum(axis=1)
        return (rho.mean(axis=1), (rho * u).sum(axis=1) / mass,
                p.mean(axis=1), (rho * e).sum(axis=1) / mass)
