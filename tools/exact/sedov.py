"""Sedov-Taylor point-blast exact solution (uniform ambient density).

A point (planar, line or spherical) release of energy E at t = 0 into a cold
(p = 0), uniform gas of density rho0 and ratio of specific heats gamma drives
a strong shock at radius

    r2(t) = (E t^2 / (alpha rho0))^(1/(j+2)),        j = geometry = 1, 2, 3.

Formulation
-----------
The closed-form similarity solution is written as in Kamm & Timmes (2007),
"On efficient generation of numerically robust Sedov solutions",
LA-UR-07-2849 (after Sedov 1959, ch. IV), specialised to omega = 0.  The
similarity variable is V, with u = V r / t; it runs from V0 = 2/((j+2) gamma)
at the centre to V2 = 4/((j+2)(gamma+1)) at the shock.  With

    a = (j+2)(gamma+1)/4           b = (gamma+1)/(gamma-1)
    c = (j+2) gamma / 2            e = (2 + j(gamma-1))/2
    d = (j+2)(gamma+1) / ((j+2)(gamma+1) - 2(2 + j(gamma-1)))
    x1 = a V,  x2 = b (c V - 1),  x3 = d (1 - e V),  x4 = b (1 - c V/gamma)

    a0 = 2/(j+2)
    a2 = -(gamma-1) / (2(gamma-1) + j)
    a1 = (j+2) gamma/(2 + j(gamma-1)) * (2 j (2-gamma)/(gamma (j+2)^2) - a2)
    a3 = j / (2(gamma-1) + j)
    a4 = (j+2) a1 / (2 - gamma)
    a5 = -2 / (2 - gamma)

the solution is, with lambda = r / r2,

    lambda = x1^-a0 x2^-a2 x3^-a1
    u / u2   = f = x1 lambda
    rho/rho2 = g = x2^a3 x3^a4 x4^a5
    p / p2   = h = x1^(a0 j) x3^(a4 - 2 a1) x4^(1 + a5)

and the post-shock (strong-shock Rankine-Hugoniot) state is, with shock
speed D = a0 r2/t,

    u2 = 2 D/(gamma+1),  rho2 = rho0 (gamma+1)/(gamma-1),  p2 = 2 rho0 D^2/(gamma+1).

All x_k equal 1 at the shock.  Numerically, V is replaced by the variable
s = ln x2 in (-inf, 0]: near the centre x2 = b(cV - 1) would otherwise be
lost to cancellation (lambda ~ x2^(-a2) with a small exponent, so r/r2 = 1e-3
already needs x2 ~ 1e-30).  lambda(s) is monotone and is inverted by a
vectorised safeguarded bisection/Newton iteration.

Energy integral
---------------
Total energy E = integral over the blast of (rho u^2/2 + p/(gamma-1)) dV gives

    alpha = sigma_j a0^2 2/(gamma^2 - 1) * int_0^1 (g f^2 + h) lambda^(j-1) dlambda

with the volume element dV = sigma_j r^(j-1) dr, sigma = (1, 2 pi, 4 pi) for
j = (1, 2, 3).  The integral is done by scipy quad in q = x2^(-a2 j), which
maps the centre to q = 0 with a finite integrand (see _alpha_integral).  It
equals Kamm & Timmes' alpha = (j-1) pi (J1 + 2 J2/(gamma-1)) for j = 2, 3 and
alpha = (J1 + 2 J2/(gamma-1))/2 for j = 1, with J1 the kinetic and J2 the
internal-energy integral (attributes J1, J2 here).  Our J1 agree with their
Table 4 to all printed digits; our J2 are slightly larger (relative 4e-4
planar, 4e-5 cylindrical, 2e-5 spherical for gamma = 1.4).  In V their J2
integrand has an integrable singularity ~ (V - V0)^(-a2 j - 1) at the centre
(strongest for planar), which is removed here by the change of variable; the
independent checks in test_sedov.py (energy by quadrature in r, PDE
residuals, mass) agree with our values.  So for gamma = 1.4 we get alpha =
0.538743 (planar; their Table 4: 0.538548), 0.984074 (cylindrical; 0.984041)
and 0.851072 (spherical; 0.851060 -- 0.851072 is the energy of their
spherical test problem, which puts the shock at r = 1 at t = 1).

Planar convention: sigma_1 = 1, i.e. E is the energy per unit area contained
in the half-space x >= 0 (the symmetric slab -r2 < x < r2 holds 2E).  This is
Kamm & Timmes' convention (factor 1/2 for j = 1 above): with it alpha(1.4,
planar) is about 0.5387 (their Table 4: 0.538548) and their planar test
problem E = 0.0673185 puts the shock at x = 0.5 at t = 1 (we get 0.49994,
the difference being their J2 error).  With the full-slab convention
(E = energy of the whole slab) alpha would be twice as large.

Scope
-----
Only omega = 0 (uniform ambient density) is implemented; for omega = 0 only
the "standard" branch of Kamm & Timmes occurs (their singular and vacuum
branches need omega >= (2(gamma-1)+j)/gamma > 0).  The removable-singularity
special cases omega = j(2-gamma) (i.e. gamma = 2) and, in spherical geometry,
omega = (7-gamma)/(gamma+1) (i.e. gamma = 7) need separate formulas and
raise ValueError, as do gamma within 1e-6 of 2, spherical gamma > 7 - 1e-4
(for gamma > 7, x3 = 0 inside (V0, V2)).  Checked for 1.05 <= gamma <= 10
otherwise.

Usage::

    sol = SedovSolution(1.4, 3, 0.851072)
    sol.alpha, sol.shock_radius(1.0)
    rho, u, p = sol.state(r, t)
    rho, u, p = sol.cell_average(r_edges, t, nsub=64)
"""

import math

import numpy as np
from scipy.integrate import quad

__all__ = ["SedovSolution"]


class SedovSolution:
    """Sedov-Taylor blast wave in a uniform, cold, ideal gas.

    Parameters
    ----------
    gamma : float
        Ratio of specific heats (> 1).
    geometry : int
        1 planar, 2 cylindrical, 3 spherical.
    energy : float
        Blast energy E: total (spherical), per unit length (cylindrical), per
        unit area of the half-space x >= 0 (planar; Kamm & Timmes convention,
        see the module docstring).
    rho0 : float
        Ambient density.
    omega : float
        Ambient density power-law exponent (rho = rho0 r^-omega); only 0.
    """

    def __init__(self, gamma, geometry, energy, rho0=1.0, omega=0.0):
        gamma = float(gamma)
        energy = float(energy)
        rho0 = float(rho0)
        if geometry not in (1, 2, 3):
            raise ValueError("geometry must be 1 (planar), 2 (cylindrical) "
                             "or 3 (spherical)")
        if not gamma > 1.0:
            raise ValueError("gamma must be > 1")
        if not energy > 0.0:
            raise ValueError("energy must be > 0")
        if not rho0 > 0.0:
            raise ValueError("rho0 must be > 0")
        if omega != 0.0:
            raise ValueError("only uniform ambient density (omega = 0) is "
                             "implemented")
        j = int(geometry)
        if abs(gamma - 2.0) < 1e-6:
            raise ValueError("gamma = 2 is a special case (omega = omega3) "
                             "that is not implemented")
        if j == 3 and gamma > 7.0 - 1e-4:
            # gamma = 7 is the special case omega = omega1; for gamma > 7 the
            # zero of x3 (V = 1/e) falls inside (V0, V2)
            raise ValueError("spherical geometry with gamma >= 7 is not "
                             "implemented")

        self.gamma = gamma
        self.geometry = j
        self.energy = energy
        self.rho0 = rho0
        self.omega = 0.0

        g = gamma
        n = j + 2.0
        self._a = n * (g + 1.0) / 4.0
        self._b = (g + 1.0) / (g - 1.0)
        self._c = n * g / 2.0
        self._e = (2.0 + j * (g - 1.0)) / 2.0
        self._d = n * (g + 1.0) / (n * (g + 1.0) - 2.0 * (2.0 + j * (g - 1.0)))
        self._a0 = 2.0 / n
        self._a2 = -(g - 1.0) / (2.0 * (g - 1.0) + j)
        self._a1 = (n * g / (2.0 + j * (g - 1.0))
                    * (2.0 * j * (2.0 - g) / (g * n * n) - self._a2))
        self._a3 = j / (2.0 * (g - 1.0) + j)
        self._a4 = n * self._a1 / (2.0 - g)
        self._a5 = -2.0 / (2.0 - g)

        self.v0 = 2.0 / (n * g)          # centre
        self.v2 = 4.0 / (n * (g + 1.0))  # shock
        self.sigma = {1: 1.0, 2: 2.0 * math.pi, 3: 4.0 * math.pi}[j]

        # ln(lambda) -> -a2 * s + C0 as s = ln x2 -> -inf
        self._lnlam_c0 = (-self._a0 * math.log(self._a * self.v0)
                          - self._a1 * math.log(self._d * (1.0 - self._e * self.v0)))
        self._check_monotone()
        self.alpha = self._alpha_integral()

    # ------------------------------------------------------------------
    # similarity functions in terms of s = ln x2 in [-inf, 0]
    # ------------------------------------------------------------------
    def _logs(self, s):
        """ln x1, ln x3, ln x4 and V at s = ln x2 (array)."""
        y = np.exp(s)                       # x2; 0 at the centre
        v = (1.0 + y / self._b) / self._c
        lx1 = np.log(self._a * v)
        lx3 = np.log(self._d * (1.0 - self._e * v))
        lx4 = np.log(self._b * (1.0 - self._c * v / self.gamma))
        return v, lx1, lx3, lx4

    def _lnlam(self, s):
        _, lx1, lx3, _ = self._logs(s)
        return -self._a0 * lx1 - self._a2 * s - self._a1 * lx3

    def _dlnlam_ds(self, s):
        """d ln(lambda) / d ln(x2)."""
        y = np.exp(s)
        v = (1.0 + y / self._b) / self._c
        dv_ds = y / (self._b * self._c)
        return (-self._a2
                + dv_ds * (-self._a0 / v
                           + self._a1 * self._e / (1.0 - self._e * v)))

    def _fgh_lnlam(self, s):
        """(f, g, h, ln lambda, V) at s = ln x2; s may be -inf (centre)."""
        s = np.asarray(s, dtype=float)
        v, lx1, lx3, lx4 = self._logs(s)
        centre = np.isneginf(s)
        s_fin = np.where(centre, 0.0, s)
        lnlam = -self._a0 * lx1 - self._a2 * s_fin - self._a1 * lx3
        lam = np.where(centre, 0.0, np.exp(lnlam))
        f = np.exp(lx1) * lam
        lng = self._a3 * s_fin + self._a4 * lx3 + self._a5 * lx4
        g = np.where(centre, 0.0, np.exp(lng))
        h = np.exp(self._a0 * self.geometry * lx1
                   + (self._a4 - 2.0 * self._a1) * lx3
                   + (1.0 + self._a5) * lx4)
        lnlam = np.where(centre, -np.inf, lnlam)
        return f, g, h, lnlam, v

    def _check_monotone(self):
        s = -np.logspace(-12, 3, 400)
        if np.any(self._dlnlam_ds(s) <= 0.0) or np.any(
                self._dlnlam_ds(np.array([0.0])) <= 0.0):
            raise ValueError("lambda(V) is not monotone for these parameters; "
                             "not the standard Sedov branch")

    def _solve_s(self, lnlam):
        """Invert ln(lambda) = lnlam (array, all < 0 and finite) for s."""
        lnlam = np.asarray(lnlam, dtype=float)
        k = -self._a2  # > 0
        # lower bracket from the centre asymptote, pushed down until valid
        lo = np.minimum((lnlam - self._lnlam_c0) / k - 10.0, -1e-300)
        for _ in range(200):
            bad = self._lnlam(lo) > lnlam
            if not np.any(bad):
                break
            lo = np.where(bad, 2.0 * lo - 10.0, lo)
        hi = np.zeros_like(lnlam)
        s = 0.5 * (lo + hi)
        # bisection, then Newton polish (lambda is monotone in s)
        for _ in range(60):
            s = 0.5 * (lo + hi)
            too_big = self._lnlam(s) > lnlam
            hi = np.where(too_big, s, hi)
            lo = np.where(too_big, lo, s)
            if np.all(hi - lo <= 1e-9 * (1.0 + np.abs(s))):
                break
        s = 0.5 * (lo + hi)
        for _ in range(3):
            step = (self._lnlam(s) - lnlam) / self._dlnlam_ds(s)
            s_new = np.minimum(s - step, 0.0)
            s = np.where((s_new >= lo) & (s_new <= hi), s_new, s)
        return s

    def functions_of_v(self, v):
        """(lambda, f, g, h) at Kamm-Timmes similarity variable V in [V0, V2]."""
        v = np.atleast_1d(np.asarray(v, dtype=float))
        if np.any(v < self.v0) or np.any(v > self.v2 * (1.0 + 1e-14)):
            raise ValueError("V must lie in [V0, V2]")
        x2 = self._b * (self._c * v - 1.0)
        with np.errstate(divide="ignore"):
            s = np.where(x2 > 0.0, np.log(np.maximum(x2, 1e-300)), -np.inf)
        s = np.minimum(s, 0.0)
        f, g, h, lnlam, _ = self._fgh_lnlam(s)
        return np.exp(lnlam), f, g, h

    def similarity(self, lam):
        """Similarity functions at lambda = r/r2 in [0, 1].

        Returns (V, f, g, h) arrays: V the Kamm-Timmes similarity variable
        (u = V r/t), and u/u2 = f, rho/rho2 = g, p/p2 = h.
        """
        lam = np.atleast_1d(np.asarray(lam, dtype=float))
        if np.any(lam < 0.0) or np.any(lam > 1.0):
            raise ValueError("lambda must lie in [0, 1]")
        s = np.full(lam.shape, -np.inf)
        inner = (lam > 0.0) & (lam < 1.0)
        s[lam >= 1.0] = 0.0
        if np.any(inner):
            s[inner] = self._solve_s(np.log(lam[inner]))
        f, g, h, _, v = self._fgh_lnlam(s)
        return v, f, g, h

    # ------------------------------------------------------------------
    # energy integral
    # ------------------------------------------------------------------
    def _alpha_integral(self):
        """alpha by quadrature of the similarity solution.

        I = int_0^1 (g f^2 + h) lambda^(j-1) dlambda
          = int_{-inf}^0 (g f^2 + h) lambda^j (dln lambda/ds) ds,   s = ln x2.
        Substituting q = exp(k j s), k = -a2 > 0 (q in (0, 1]), ds = dq/(k j q):
        lambda^j / q = (x1^-a0 x3^-a1)^j is finite at the centre q = 0, so
        the integrand in q is bounded.  The kinetic (g f^2) and internal (h)
        parts are integrated separately to give Kamm & Timmes' J1 and J2.
        """
        j = self.geometry
        k = -self._a2

        def parts(q):
            if q <= 0.0:
                s, sd = -np.inf, -1e300
            else:
                s = sd = math.log(q) / (k * j)
            f, g, h, _, _ = self._fgh_lnlam(np.array([s]))
            _, lx1, lx3, _ = self._logs(np.array([s]))
            ratio = math.exp(j * float(-self._a0 * lx1[0] - self._a1 * lx3[0]))
            jac = ratio * float(self._dlnlam_ds(np.array([sd]))[0]) / (k * j)
            return float(g[0] * f[0] ** 2) * jac, float(h[0]) * jac

        opts = dict(epsabs=0.0, epsrel=1e-13, limit=400)
        kin, _ = quad(lambda q: parts(q)[0], 0.0, 1.0, **opts)
        thm, _ = quad(lambda q: parts(q)[1], 0.0, 1.0, **opts)
        g = self.gamma
        fac = 4.0 * self._a0 ** 2 / (g * g - 1.0)
        self.J1 = fac * kin                       # Kamm & Timmes J1
        self.J2 = 0.5 * (g - 1.0) * fac * thm     # Kamm & Timmes J2
        return 0.5 * self.sigma * fac * (kin + thm)

    # ------------------------------------------------------------------
    # physical solution
    # ------------------------------------------------------------------
    def shock_radius(self, t):
        """r2(t) = (E t^2 / (alpha rho0))^(1/(j+2))."""
        t = np.asarray(t, dtype=float)
        r2 = (self.energy * t * t / (self.alpha * self.rho0)) ** (
            1.0 / (self.geometry + 2.0))
        return float(r2) if r2.ndim == 0 else r2

    def shock_speed(self, t):
        return self._a0 * self.shock_radius(t) / t

    def post_shock(self, t):
        """Immediate post-shock (rho2, u2, p2) at time t."""
        g = self.gamma
        dsh = self.shock_speed(t)
        return (self.rho0 * self._b, 2.0 * dsh / (g + 1.0),
                2.0 * self.rho0 * dsh * dsh / (g + 1.0))

    def state(self, r, t):
        """(rho, u, p) at positions r and time t > 0.

        Points with |r| <= r2(t) are in the blast (the shock itself gets the
        post-shock state); outside, the ambient state (rho0, 0, 0).  For the
        planar geometry r may be negative (mirror-symmetric solution, u odd
        in x); for cylindrical/spherical r must be >= 0.
        """
        t = float(t)
        if not t > 0.0:
            raise ValueError("t must be > 0")
        r = np.asarray(r, dtype=float)
        shape = r.shape
        r = r.ravel()
        if self.geometry > 1 and np.any(r < 0.0):
            raise ValueError("radius must be >= 0 for cylindrical/spherical")
        ar = np.abs(r)
        sign = np.where(r < 0.0, -1.0, 1.0)
        r2 = self.shock_radius(t)
        rho2, u2, p2 = self.post_shock(t)
        rho = np.full(r.shape, self.rho0)
        u = np.zeros(r.shape)
        p = np.zeros(r.shape)
        inside = ar <= r2
        if np.any(inside):
            _, f, g, h = self.similarity(ar[inside] / r2)
            rho[inside] = rho2 * g
            u[inside] = u2 * f * sign[inside]
            p[inside] = p2 * h
        return rho.reshape(shape), u.reshape(shape), p.reshape(shape)

    def cell_average(self, r_edges, t, nsub=64):
        """Cell averages over cells [r_i, r_{i+1}] at time t.

        Volume element dV ~ r^(j-1) dr.  Returns arrays (rho, u, p) of length
        len(r_edges) - 1:
          rho = int rho dV / int dV          (volume-weighted density)
          u   = int rho u dV / int rho dV    (mass-weighted velocity)
          p   = int p dV / int dV            (volume-weighted pressure)
        Each cell is split at the shock (and, planar, at -r2 and 0) and each
        piece is integrated with nsub-point Gauss-Legendre quadrature.
        """
        edges = np.asarray(r_edges, dtype=float).ravel()
        if edges.size < 2 or np.any(np.diff(edges) <= 0.0):
            raise ValueError("r_edges must be strictly increasing, >= 2 values")
        if self.geometry > 1 and edges[0] < 0.0:
            raise ValueError("radius must be >= 0 for cylindrical/spherical")
        j = self.geometry
        r2 = self.shock_radius(t)
        ncell = edges.size - 1
        brk = [r2] if j > 1 else [-r2, 0.0, r2]
        lo_l, hi_l, id_l = [], [], []
        for i in range(ncell):
            a, b = edges[i], edges[i + 1]
            pts = [a] + [x for x in brk if a < x < b] + [b]
            for k in range(len(pts) - 1):
                lo_l.append(pts[k])
                hi_l.append(pts[k + 1])
                id_l.append(i)
        lo = np.array(lo_l)
        hi = np.array(hi_l)
        cid = np.array(id_l)
        xg, wg = np.polynomial.legendre.leggauss(int(nsub))
        half = 0.5 * (hi - lo)
        mid = 0.5 * (hi + lo)
        r = mid[:, None] + half[:, None] * xg[None, :]
        w = half[:, None] * wg[None, :]
        if j > 1:
            w = w * r ** (j - 1)
        rho, u, p = self.state(r, t)
        mass = np.bincount(cid, (w * rho).sum(axis=1), minlength=ncell)
        mom = np.bincount(cid, (w * rho * u).sum(axis=1), minlength=ncell)
        pv = np.bincount(cid, (w * p).sum(axis=1), minlength=ncell)
        a, b = edges[:-1], edges[1:]
        vol = (b - a) if j == 1 else (b ** j - a ** j) / j
        ubar = np.divide(mom, mass, out=np.zeros(ncell), where=mass > 0.0)
        return mass / vol, ubar, pv / vol
