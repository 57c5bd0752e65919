#!/usr/bin/env python3
"""Kingery-Bulmash airblast parameters of TNT from Swisdak's simplified fits.

    kingery_bulmash.py --mass W --distance R [R ...] [--free-air] [--reflection F]

Source: M. M. Swisdak, "Simplified Kingery Airblast Calculations",
NSWC Indian Head Division, 1994 (DTIC ADA526744): polynomial fits in ln Z,
metric units, to the Kingery-Bulmash curves (C. N. Kingery and G. Bulmash,
ARBRL-TR-02555, 1984) for a HEMISPHERICAL SURFACE BURST of TNT. Each
parameter is

    Y = exp(A + B ln Z + C (ln Z)^2 + D (ln Z)^3 + E (ln Z)^4 + F (ln Z)^5)

with the scaled distance Z = R / W^(1/3) in m/kg^(1/3) (R in m, W in kg of
TNT), the coefficients of the range of Z that contains Z (table RANGES
below, copied from Swisdak's tables). Y is:
  - arrival time:          ms / kg^(1/3) (multiplied by W^(1/3) here: ms)
  - incident overpressure: kPa (not scaled)
  - positive duration:     ms / kg^(1/3) (multiplied by W^(1/3): ms)
  - incident impulse:      kPa ms / kg^(1/3) (multiplied by W^(1/3): kPa ms)
A Z outside a parameter's fitted ranges raises ValueError (no
extrapolation). At a boundary between two ranges the lower range is used;
the fits of neighbouring ranges agree there within 2.4 % (the impulse at
Z = 2.38), within 1.2 % for the others (tools/test_kingery_bulmash.py).

Free air (a spherical burst, --free-air): a free-air burst of W is taken as
a surface burst of W / F, F the ground reflection factor (--reflection,
default 1.8: UFC 3-340-02's factor for a surface burst on ordinary ground,
part of the energy going into the crater and ground shock; a perfectly rigid
ground would reflect all of it, F = 2). The free-air numbers therefore
depend on F: F = 1.8 gives an overpressure 6 to 8 % above F = 2's for
Z = 0.5 to 3 (1 kg: 886 against 819 kPa at 1 m), arrivals 2 to 3 % earlier;
tools/blast_kb_plot.py shows both. Z printed for free air is R / W^(1/3) of
the free-air charge W; the fits are evaluated at R / (W/F)^(1/3).

Importable: hemispherical(param, R, W), free_air(param, R, W, reflection),
blast(R, W, free=False, reflection=1.8) and scaled(param, Z);
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
RANGES = {
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


def fit(coeffs, z):
    """exp(sum_i c_i (ln z)^i) for one range's coefficients (no range check)."""
    lz = math.log(z)
    return math.exp(sum(c * lz ** i for i, c in enumerate(coeffs)))


def z_range(param):
    """The (lowest, highest) Z of a parameter's fits."""
    r = RANGES[param]
    return r[0][0], r[-1][1]


def scaled(param, z):
    """The scaled value of param at the hemispherical scaled distance z
    (m/kg^(1/3)): kPa for the overpressure, ms/kg^(1/3) for the times,
    kPa ms/kg^(1/3) for the impulse. ValueError outside the fitted ranges."""
    if param not in RANGES:
        raise ValueError(f"unknown parameter {param!r} (one of {', '.join(PARAMS)})")
    for lo, hi, coeffs in RANGES[param]:
        if lo <= z <= hi:
            return fit(coeffs, z)
    lo, hi = z_range(param)
    raise ValueError(f"Kingery-Bulmash {param}: scaled distance Z = {z:.6g} m/kg^(1/3) is outside "
                     f"the fitted range {lo:g} to {hi:g} (hemispherical surface burst; Swisdak 1994)")


def hemispherical(param, r, w):
    """param of a hemispherical surface burst of w kg TNT at r m (ms, kPa, kPa ms)."""
    if not (w > 0 and r > 0):
        raise ValueError(f"distance ({r}) and mass ({w}) must be positive")
    cube = w ** (1.0 / 3.0)
    y = scaled(param, r / cube)
    return y * cube if CUBE_ROOT_SCALED[param] else y


def free_air(param, r, w, reflection=1.8):
    """param of a free-air (spherical) burst of w kg TNT at r m: that of a
    surface burst of w / reflection."""
    if not reflection > 0:
        raise ValueError(f"reflection factor must be positive, not {reflection}")
    return hemispherical(param, r, w / reflection)


def blast(r, w, free=False, reflection=1.8):
    """All four parameters at r m of w kg TNT, a dict param -> value."""
    we = w / reflection if free else w
    return {p: hemispherical(p, r, we) for p in PARAMS}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 epilog="Units: distance m, mass kg TNT; prints ms, kPa, kPa ms.")
    ap.add_argument("--mass", type=float, required=True, help="TNT mass, kg")
    ap.add_argument("--distance", type=float, nargs="+", required=True, help="distances from the charge, m")
    ap.add_argument("--free-air", action="store_true",
                    help="spherical free-air burst: a surface burst of mass/REFLECTION")
    ap.add_argument("--reflection", type=float, default=1.8,
                    help="ground reflection factor for --free-air (default 1.8, UFC 3-340-02; 2 = rigid ground)")
    a = ap.parse_args(argv)
    if a.free_air:
        print(f"# free-air burst of {a.mass:g} kg TNT = hemispherical surface burst of "
              f"{a.mass:g}/{a.reflection:g} = {a.mass / a.reflection:.6g} kg (Swisdak 1994 fits)")
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
