"""Symmetric plate impact of an elastic-perfectly-plastic solid in uniaxial
strain: the two-wave (elastic precursor, plastic shock) solution.

The solid is the particles' model with `strength = 'bilinear'`, tangent
modulus 0: a hypoelastic deviator (shear modulus G) with von Mises yield
stress Y, and the Mie-Gruneisen pressure of modules/eos/eos_mie_gruneisen.f90,
p = K(mu) + gamma0 rho0 e with K from the linear Us = c0 + s1 up Hugoniot
(K = rho0 c0^2 mu in tension). Compression is positive here:
sigma = -sigma_xx.

In uniaxial strain the deviator grows as s_x = (4/3) G ln(rho/rho0) until
it reaches the yield surface s_x = (2/3) Y, at ln(rho1/rho0) = Y/(2G): the
Hugoniot elastic limit. A flyer at V hits a target of the same solid at
rest; by symmetry the material between the two wave systems moves at
V/2. Into the target run

* the elastic precursor, a jump from (rho0, u = 0, sigma = 0, e = 0) to the
  elastic limit (rho1, u1, sigma1 = p(rho1, e1) + 2Y/3, e1), at U1:
  rho0 U1 = rho1 (U1 - u1), sigma1 = rho0 U1 u1, e1 = sigma1 (1/rho0 - 1/rho1)/2;
* the plastic shock, from that state to (rhof, V/2, sigmaf = p(rhof, ef) +
  2Y/3, ef), at Up: rho1 (Up - u1) = rhof (Up - V/2) = m, sigmaf - sigma1 =
  m (V/2 - u1), ef - e1 = (sigmaf + sigma1)(1/rho1 - 1/rhof)/2;

e being the specific internal energy (the work of the whole stress, as the
particles book it). Each is one equation in one unknown (sigma1; rhof),
solved by bisection to round-off. The structure exists while Up < U1 (a
plastic shock slower than the precursor); `solve` raises ValueError
otherwise, or when the data are not positive and finite.

Usage::

    s = solve(rho0=2.7, c0=0.533, s1=1.34, gamma0=2.0, g=0.271, y=0.0029, v=0.05)
    s["sigma1"], s["u1"], s["U1"], s["sigmaf"], s["rhof"], s["Up"]
"""

import math

__all__ = ["mg_pressure", "solve"]


def mg_pressure(rho, e, rho0, c0, s1, gamma0):
    """The Mie-Gruneisen pressure of eos_mie_gruneisen.f90 (below its mu_max)."""
    mu = rho / rho0 - 1.0
    if mu >= 0.0:
        ph = rho0 * c0 * c0 * mu * (1.0 + mu) / (1.0 - (s1 - 1.0) * mu) ** 2
        k = ph * (1.0 - gamma0 * mu / (2.0 * (1.0 + mu)))
    else:
        k = rho0 * c0 * c0 * mu
    return k + gamma0 * rho0 * e


def _bisect(f, lo, hi):
    """The root of f in [lo, hi] (f(lo) and f(hi) of opposite signs), to round-off."""
    flo = f(lo)
    if flo == 0.0:
        return lo
    if flo * f(hi) > 0.0:
        raise ValueError("no root in the bracket")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        fm = f(mid)
        if fm == 0.0:
            return mid
        if (fm < 0.0) == (flo < 0.0):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


def solve(rho0, c0, s1, gamma0, g, y, v):
    """The two waves' states and speeds (module notes) as a dict: rho1,
    sigma1, u1, e1, U1 (precursor), rhof, sigmaf, uf, ef, Up (plastic shock)."""
    for name, val in (("rho0", rho0), ("c0", c0), ("g", g), ("y", y), ("v", v)):
        if not (val > 0.0 and math.isfinite(val)):
            raise ValueError(f"{name} must be positive and finite, got {val}")
    rho1 = rho0 * math.exp(y / (2.0 * g))

    def precursor(sigma):
        e = 0.5 * sigma * (1.0 / rho0 - 1.0 / rho1)
        return mg_pressure(rho1, e, rho0, c0, s1, gamma0) + 2.0 * y / 3.0 - sigma

    hi = 1.0
    while precursor(hi) > 0.0:
        hi *= 2.0
    sigma1 = _bisect(precursor, 0.0, hi)
    u1_over_u = 1.0 - rho0 / rho1
    big_u1 = math.sqrt(sigma1 / (rho0 * u1_over_u))
    u1 = big_u1 * u1_over_u
    e1 = 0.5 * sigma1 * (1.0 / rho0 - 1.0 / rho1)
    uf = 0.5 * v
    if not uf > u1:
        raise ValueError(f"V/2 = {uf} does not pass the elastic limit's velocity {u1}: no plastic shock")

    def shock(rhof):
        m = (uf - u1) / (1.0 / rho1 - 1.0 / rhof)
        sf = sigma1 + m * (uf - u1)
        ef = e1 + 0.5 * (sf + sigma1) * (1.0 / rho1 - 1.0 / rhof)
        return mg_pressure(rhof, ef, rho0, c0, s1, gamma0) + 2.0 * y / 3.0 - sf

    # (the shock function tends to -inf as rhof -> rho1+ (infinite mass flux)
    # and grows with rhof; the Hugoniot's singularity bounds the bracket)
    top = rho0 * (1.0 + 0.99 / (s1 - 1.0)) if s1 > 1.0 else 10.0 * rho0
    lo = rho1 * (1.0 + 1e-12)
    hi = rho1 * 1.001
    while shock(hi) < 0.0:
        hi = min(rho1 + 2.0 * (hi - rho1), top)
        if hi >= top and shock(hi) < 0.0:
            raise ValueError("no plastic shock state below the Hugoniot's singularity")
    rhof = _bisect(shock, lo, hi)
    m = (uf - u1) / (1.0 / rho1 - 1.0 / rhof)
    sigmaf = sigma1 + m * (uf - u1)
    ef = e1 + 0.5 * (sigmaf + sigma1) * (1.0 / rho1 - 1.0 / rhof)
    big_up = u1 + m / rho1
    if not big_up < big_u1:
        raise ValueError(f"the plastic shock ({big_up}) overtakes the precursor ({big_u1}): one wave")
    return dict(rho1=rho1, sigma1=sigma1, u1=u1, e1=e1, U1=big_u1,
                rhof=rhof, sigmaf=sigmaf, uf=uf, ef=ef, Up=big_up)
