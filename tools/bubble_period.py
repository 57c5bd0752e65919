#!/usr/bin/python3
"""The first bubble period of an underwater charge from a run's material
sums, against the Rayleigh-Willis formula.

    bubble_period.py OUT/NAME_matsum.txt --material tnt --charge-kg W
                     --p-inf P [--copies 8] [--water-density 1.0]

The bubble is the explosive's material: its volume (the last column of the
matsum file, times --copies for the symmetry planes through the charge,
8 for an octant) grows to a maximum and falls to a first minimum. The
period T is the time of that minimum (from detonation, t = 0), refined by a
parabola through the three rows about it; R_max is the radius of the
sphere of the maximum volume. The deck's units must be mm, us, g/cm^3,
GPa (kJ/g); --p-inf is the ambient pressure in GPa.

Printed beside them:
  - the Rayleigh-Willis similitude for TNT (Cole, Underwater Explosions,
    1948, Sect. 8.4; Swisdak, NSWC TR 76-116): T = K W^(1/3) / Z^(5/6),
    R_max = J W^(1/3) / Z^(1/3), with K = 2.11 s m^(5/6) kg^(-1/3) and
    J = 3.38 m^(4/3) kg^(-1/3), Z = p_inf / (rho g) the hydrostatic head
    in m (W in kg, T in s);
  - the Rayleigh-Willis formula with the run's own bubble energy,
    T = 1.135 rho^(1/2) E^(1/3) / p_inf^(5/6), E = p_inf V_max + the
    products' internal energy at the maximum (its fraction of the charge's
    energy W e0 is printed; --specific-energy e0 defaults to the library
    TNT's, 7.0 GPa / 1.63 g/cm^3).
"""
import argparse
import math
import sys

import numpy as np

G = 9.81


def read(path, material):
    t, vol, ie = [], [], []
    for line in open(path):
        if line.startswith("#"):
            continue
        f = line.split()
        if f[1] == "material" and f[3] == material:
            t.append(float(f[0]))
            ie.append(float(f[9]))
            vol.append(float(f[10]))
    if not t:
        sys.exit(f"FAIL: no rows of material {material} in {path}")
    return np.array(t), np.array(vol), np.array(ie)


def parabola_vertex(t, v, k):
    """Time and value of the parabola's vertex through rows k-1, k, k+1."""
    if k == 0 or k == len(t) - 1:
        return t[k], v[k]
    a, b, c = np.polyfit(t[k - 1:k + 2], v[k - 1:k + 2], 2)
    if a == 0.0:
        return t[k], v[k]
    tv = -b / (2 * a)
    return tv, c - b * b / (4 * a)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("matsum")
    ap.add_argument("--material", required=True)
    ap.add_argument("--charge-kg", type=float, required=True)
    ap.add_argument("--p-inf", type=float, required=True, help="ambient pressure, GPa")
    ap.add_argument("--copies", type=float, default=8.0)
    ap.add_argument("--water-density", type=float, default=1.0, help="g/cm^3")
    ap.add_argument("--specific-energy", type=float, default=7.0 / 1.63, help="the charge's, kJ/g")
    a = ap.parse_args()
    t, vol, ie = read(a.matsum, a.material)
    vol = vol * a.copies
    kmax = int(np.argmax(vol))
    later = np.nonzero(np.diff(vol[kmax:]) > 0)[0]
    if not later.size:
        sys.exit(f"FAIL: the bubble has not collapsed by t = {t[-1]:g} us (largest volume at {t[kmax]:g})")
    kmin = kmax + int(later[0])
    tmax, vmax = parabola_vertex(t, vol, kmax)
    tmin, vmin = parabola_vertex(t, vol, kmin)
    r_max = (3 * vmax / (4 * math.pi)) ** (1 / 3)
    r_min = (3 * vmin / (4 * math.pi)) ** (1 / 3)
    p_pa = a.p_inf * 1e9
    rho = a.water_density * 1e3
    z = p_pa / (rho * G)
    w3 = a.charge_kg ** (1 / 3)
    t_sim = 2.11 * w3 / z ** (5 / 6) * 1e6
    r_sim = 3.38 * w3 / z ** (1 / 3) * 1e3
    e0 = a.charge_kg * a.specific_energy * 1e6       # J
    e_b = a.p_inf * vmax + ie[kmax] * a.copies      # GPa mm^3 = J
    t_rw = 1.135 * math.sqrt(rho) * e_b ** (1 / 3) / p_pa ** (5 / 6) * 1e6
    print(f"bubble ({a.material}): largest at t = {tmax:.1f} us, R_max = {r_max:.2f} mm; "
          f"first minimum at t = {tmin:.1f} us (R_min = {r_min:.2f} mm)")
    print(f"period {tmin:.1f} us against the Rayleigh-Willis similitude (K 2.11, head Z = {z:.1f} m) "
          f"{t_sim:.1f} us: {tmin / t_sim - 1:+.1%}; R_max against J 3.38: {r_sim:.2f} mm: {r_max / r_sim - 1:+.1%}")
    print(f"bubble energy p_inf V_max + products' internal energy = {e_b:.4g} J "
          f"({e_b / e0:.1%} of the charge's {e0:.4g} J); "
          f"Rayleigh-Willis with it: {t_rw:.1f} us: {tmin / t_rw - 1:+.1%}")


if __name__ == "__main__":
    main()
