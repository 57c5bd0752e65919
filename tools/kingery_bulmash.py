#!/usr/bin/env python3
"""Kingery-Bulmash airblast parameters of TNT: surface burst and free air.

    kingery_bulmash.py --mass W --distance R [R ...] [--free-air [--reflection F]]

Two sets of fits to the Kingery-Bulmash curves (C. N. Kingery and G.
Bulmash, "Airblast Parameters from TNT Spherical Air Burst and
Hemispherical Surface Burst", ARBRL-TR-02555, 1984; the curves of UFC
3-340-02, Figs. 2-7 and 2-15), metric units, scaled distance
Z = R / W^(1/3) in m/kg^(1/3) (R in m, W in kg of TNT). Each parameter is
given, per range of Z, as
  - arrival time:          ms / kg^(1/3) (multiplied by W^(1/3) here: ms)
  - incident overpressure: kPa (not scaled)
  - positive duration:     ms / kg^(1/3) (multiplied by W^(1/3): ms)
  - incident impulse:      kPa ms / kg^(1/3) (multiplied by W^(1/3): kPa ms)

HEMISPHERICAL SURFACE BURST (the default): M. M. Swisdak, "Simplified
Kingery Airblast Calculations", NSWC Indian Head Division, 1994 (DTIC
ADA526744), polynomials in ln Z,
    Y = exp(A + B ln Z + C (ln Z)^2 + D (ln Z)^3 + E (ln Z)^4 + F (ln Z)^5),
the coefficients of the range that contains Z (table SURFACE).

SPHERICAL FREE-AIR BURST (--free-air): Kingery and Bulmash's own fits of
the free-air curves, polynomials in U = u0 + u1 log10 Z,
    log10 Y = c0 + c1 U + c2 U^2 + ...,
(table FREE_AIR; the coefficients as the report gives them, transcribed
from two public compilations that agree, the duration's second range's c0
chosen by continuity where they differ). Its hemispherical set evaluated
the same way agrees with Swisdak's within 0.3 % at Z = 0.5 to 3, which
checks the form.

A free-air burst is also often approximated as a surface burst of W / F,
F the ground reflection factor (--free-air --reflection F; UFC 3-340-02
takes 1.8 for a surface burst on ordinary ground, 2 for a rigid ground).
At Z = 0.5, 1, 2 and 3 that approximation with F = 1.8 is 9, 5, 7 and 6 %
below the free-air fits' overpressure and arrives 5, 3, 3 and 2 % later;
impulse and duration agree within 2 %. The free-air fits are the reference
for a charge in free air.

A Z outside a parameter's fitted ranges raises ValueError (no
extrapolation). At a boundary between two ranges the lower range is used;
the fits of neighbouring ranges agree there within 2.4 %
(tools/test_kingery_bulmash.py).

Importable: hemispherical(param, R, W), free_air(param, R, W,
reflection=None) (None: the free-air fits; F: a surface burst of W/F),
blast(R, W, free=False, reflection=None) and scaled(param, Z, free=False);
param is one of PARAMS.
"""
import argparse
import math
import sys

PARAMS = ("arrival", "overpressure", "duration", "impulse")
UNITS = {"arrival": "ms", "overpressure": "kPa", "duration": "ms", "impulse": "kPa ms"}
# scaled by W^(1/3) (times and impulses) or not (pressure)
CUBE_ROOT_SCALED = {"arrival": True, "overpressure": False, "duration": True, "impulse": True}

# (Z_low, Z_high, (A, B, C, D, E, F)) per parameter: Swisdak 1994, metric
# (Z in m/kg^(1/3)), hemispherical surface burst of TNT.
SURFACE = {
    "arrival": [
        (0.06, 1.50, (-0.7604, 1.8058, 0.1257, -0.0437, -0.0310, -0.00669)),
        (1.50, 40.0, (-0.7137, 1.5732, 0.5561, -0.4213, 0.1054, -0.00929)),
    ],
    "overpressure": [
        (0.2, 2.9, (7.2106, -2.1069, -0.3229, 0.1117, 0.0685)),
        (2.9, 23.8, (7.5938, -3.0523, 0.40977, 0.0261, -0.01267)),
        (23.8, 198.5, (6.0536, -1.4066)),
    ],
    "duration": [
        (0.2, 1.02, (0.5426, 3.2299, -1.5931, -5.9667, -4.0815, -0.9149)),
        (1.02, 2.8, (0.5440, 2.7082, -9.7354, 14.3425, -9.7791, 2.8535)),
        (2.8, 40.0, (-2.4608, 7.1639, -5.6215, 2.2711, -0.44994, 0.03486)),
    ],
    "impulse": [
        (0.2, 0.96, (5.522, 1.117, 0.6, -0.292, -0.087)),
        (0.96, 2.38, (5.465, -0.308, -1.464, 1.362, -0.432)),
        (2.38, 33.7, (5.2749, -0.4677, -0.2499, 0.0588, -0.00554)),
        (33.7, 158.7, (5.9825, -1.062)),
    ],
}

# (Z_low, Z_high, (u0, u1), (c0, c1, ...)) per parameter: Kingery and
# Bulmash 1984, metric, spherical free-air burst of TNT; log10 Y = sum c_i U^i
# with U = u0 + u1 log10 Z.
FREE_AIR = {
    "arrival": [
        (0.0531, 40.0, (-0.253273111999, 1.37407043777),
         (0.0720707787637, 1.36456871214, -0.0570035692784, -0.182832224796, 0.0118851436014,
          0.0432648687627, -0.0007997367834, -0.00436073555033)),
    ],
    "overpressure": [
        (0.0531, 40.0, (-0.214362789151, 1.35034249993),
         (2.611368669, -1.69012801396, 0.00804973591951, 0.336743114941, -0.00516226351334,
          -0.0809228619888, -0.00478507266747, 0.00793030472242, 0.0007684469735)),
    ],
    "duration": [
        (0.147, 0.888, (2.26367268496, 5.11588554305),
         (-0.686608550419, 0.164953518069, 0.127788499497, 0.00291430135946, 0.00187957449227,
          0.0173413962543, 0.00269739758043, -0.00361976502798, -0.00100926577934)),
        (0.888, 2.28, (-1.33361206714, 9.2996288611),
         (0.23031841078, -0.0297944268969, 0.0306329542941, 0.0183405574074, -0.0173964666286,
          -0.00106321963576, 0.0056206003128, 0.0001618217499, -0.0006860188944)),
        (2.28, 40.0, (-3.13005805346, 3.1524725364),
         (0.621036276475, 0.0967031995552, -0.00801302059667, 0.00482705779732, 0.00187587272287,
          -0.00246738509321, -0.000841116668, 0.0006193291052)),
    ],
    "impulse": [
        (0.0531, 0.792, (2.34723921354, 3.24299066475),
         (2.38830516757, -0.443749377691, 0.168825414684, 0.0348138030308, -0.010435192824)),
        (0.792, 40.0, (-1.75305660315, 2.30629231803),
         (1.55197227115, -0.40463292088, -0.0142721946082, 0.00912366316617, -0.0006750681404,
          -0.00800863718901, 0.00314819515931, 0.00152044783382, -0.0007470265899)),
    ],
}


def fit(coeffs, z):
    """exp(sum_i c_i (ln z)^i) for one surface-burst range's coefficients (no range check)."""
    lz = math.log(z)
    return math.exp(sum(c * lz ** i for i, c in enumerate(coeffs)))


def fit_free(u, coeffs, z):
    """10^(sum_i c_i U^i), U = u0 + u1 log10 z, for one free-air range (no range check)."""
    uz = u[0] + u[1] * math.log10(z)
    return 10.0 ** sum(c * uz ** i for i, c in enumerate(coeffs))


def ranges(param, free=False):
    """A parameter's ranges as (Z_low, Z_high, function of Z)."""
    table = FREE_AIR if free else SURFACE
    if param not in table:
        raise ValueError(f"unknown parameter {param!r} (one of {', '.join(PARAMS)})")
    if free:
        return [(lo, hi, lambda z, u=u, c=c: fit_free(u, c, z)) for lo, hi, u, c in table[param]]
    return [(lo, hi, lambda z, c=c: fit(c, z)) for lo, hi, c in table[param]]


def z_range(param, free=False):
    """The (lowest, highest) Z of a parameter's fits."""
    r = ranges(param, free)
    return r[0][0], r[-1][1]


def scaled(param, z, free=False):
    """The scaled value of param at the scaled distance z (m/kg^(1/3)) of a
    surface burst (free: of a free-air burst): kPa for the overpressure,
    ms/kg^(1/3) for the times, kPa ms/kg^(1/3) for the impulse. ValueError
    outside the fitted ranges."""
    r = ranges(param, free)
    for lo, hi, f in r:
        if lo <= z <= hi:
            return f(z)
    what = "spherical free-air burst; Kingery-Bulmash 1984" if free else "hemispherical surface burst; Swisdak 1994"
    raise ValueError(f"Kingery-Bulmash {param}: scaled distance Z = {z:.6g} m/kg^(1/3) is outside "
                     f"the fitted range {r[0][0]:g} to {r[-1][1]:g} ({what})")


def burst(param, r, w, free):
    """param at r m of w kg TNT, from the free-air or the surface-burst fits."""
    if not (w > 0 and r > 0):
        raise ValueError(f"distance ({r}) and mass ({w}) must be positive")
    cube = w ** (1.0 / 3.0)
    y = scaled(param, r / cube, free)
    return y * cube if CUBE_ROOT_SCALED[param] else y


def hemispherical(param, r, w):
    """param of a hemispherical surface burst of w kg TNT at r m (ms, kPa, kPa ms)."""
    return burst(param, r, w, False)


def free_air(param, r, w, reflection=None):
    """param of a free-air (spherical) burst of w kg TNT at r m: from the
    free-air fits, or (reflection F given) that of a surface burst of w / F."""
    if reflection is None:
        return burst(param, r, w, True)
    if not reflection > 0:
        raise ValueError(f"reflection factor must be positive, not {reflection}")
    return hemispherical(param, r, w / reflection)


def blast(r, w, free=False, reflection=None):
    """All four parameters at r m of w kg TNT, a dict param -> value."""
    if free:
        return {p: free_air(p, r, w, reflection) for p in PARAMS}
    return {p: hemispherical(p, r, w) for p in PARAMS}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 epilog="Units: distance m, mass kg TNT; prints ms, kPa, kPa ms.")
    ap.add_argument("--mass", type=float, required=True, help="TNT mass, kg")
    ap.add_argument("--distance", type=float, nargs="+", required=True, help="distances from the charge, m")
    ap.add_argument("--free-air", action="store_true",
                    help="spherical free-air burst (Kingery-Bulmash's free-air fits)")
    ap.add_argument("--reflection", type=float,
                    help="with --free-air: a surface burst of mass/REFLECTION instead of the free-air fits "
                         "(UFC 3-340-02: 1.8; 2 = rigid ground)")
    a = ap.parse_args(argv)
    if a.reflection is not None and not a.free_air:
        sys.exit("kingery_bulmash.py: --reflection needs --free-air")
    if a.free_air and a.reflection is not None:
        print(f"# free-air burst of {a.mass:g} kg TNT taken as a hemispherical surface burst of "
              f"{a.mass:g}/{a.reflection:g} = {a.mass / a.reflection:.6g} kg (Swisdak 1994 fits)")
    elif a.free_air:
        print(f"# spherical free-air burst of {a.mass:g} kg TNT (Kingery-Bulmash 1984 free-air fits)")
    else:
        print(f"# hemispherical surface burst of {a.mass:g} kg TNT (Swisdak 1994 fits)")
    print(f"# {'R_m':>8} {'Z':>8} {'arrival_ms':>11} {'overpressure_kPa':>17} {'duration_ms':>12} {'impulse_kPa_ms':>15}")
    try:
        for r in a.distance:
            b = blast(r, a.mass, a.free_air, a.reflection)
            print(f"  {r:8.4g} {r / a.mass ** (1 / 3):8.4g} {b['arrival']:11.4g} {b['overpressure']:17.5g} "
                  f"{b['duration']:12.4g} {b['impulse']:15.5g}")
    except ValueError as e:
        sys.exit(f"kingery_bulmash.py: {e}")


if __name__ == "__main__":
    main()
