#!/usr/bin/python3
"""A TNT charge's underwater shock at gauges against the published
similitude (Cole; Swisdak, NSWC TR 76-116): peak overpressure
P = 52.4 (W^(1/3)/R)^1.13 MPa and its e-fold decay time
theta = 0.084 W^(1/3) (W^(1/3)/R)^-0.23 ms, W the charge's mass in kg, R the
distance in m.

    water_similitude.py GAUGES.txt --charge-kg W --radii R1 R2 ... [--units mm-us-GPa]

The gauges of the file are taken in order, their distances R1, R2, ...
repeated (the hard cases put the same radii on the axis and then on the
diagonal). The overpressure is p minus the gauge's first row; the peak its
largest value; theta the time from the peak to the first row at or below
peak/e (nan if the file ends first). Units: the deck's, mm, us and GPa
(the only ones read here). Prints one line per gauge: the distance R, the
peak and theta beside the similitude's, and their relative differences.
Exit status 0; 1 for a file that is not a gauge file or has fewer gauges
than radii.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_gauges  # noqa: E402


def similitude(charge_kg, r_mm):
    """(peak overpressure in GPa, theta in us) of the similitude at r_mm."""
    w3 = charge_kg ** (1.0 / 3.0)
    z = w3 / (r_mm * 1.0e-3)
    return 52.4e-3 * z ** 1.13, 84.0 * w3 * z ** -0.23


def gauge_errors(path, charge_kg, radii):
    """[(g, r_mm, peak, theta, peak_sim, theta_sim)] for the file's gauges in
    order, radii repeated over them."""
    names, data, _ = plot_gauges.read_table(path)
    t = data[:, names.index("time")]
    gauges = sorted(int(n.split("_")[1]) for n in names if n.startswith("pressure_"))
    if len(gauges) < len(radii):
        raise SystemExit(f"{path}: {len(gauges)} gauges, fewer than the {len(radii)} radii")
    rows = []
    for k, g in enumerate(gauges):
        p = data[:, names.index(f"pressure_{g}")]
        p = p - p[0]
        i = int(np.argmax(p))
        after = np.nonzero(p[i:] <= p[i] / np.e)[0]
        theta = t[i + after[0]] - t[i] if after.size else float("nan")
        r = radii[k % len(radii)]
        rows.append((g, r, p[i], theta) + similitude(charge_kg, r))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("gauges")
    ap.add_argument("--charge-kg", type=float, required=True)
    ap.add_argument("--radii", type=float, nargs="+", required=True, help="gauge distances, mm")
    a = ap.parse_args()
    for g, r, p, th, ps, ts in gauge_errors(a.gauges, a.charge_kg, a.radii):
        print(f"gauge {g}: R = {r:g} mm, peak {p * 1e3:.1f} MPa (similitude {ps * 1e3:.1f}, {p / ps - 1:+.1%}), "
              f"theta {th:.2f} us (similitude {ts:.2f}, {th / ts - 1:+.0%})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
